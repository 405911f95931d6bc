fn main() {
    use glam as _;
}
