//! Numbers in G-code words: the shortest decimal text of a value rounded to the profile's
//! `gcode.decimals`.

/// `v` rounded to `decimals` places, without trailing zeros, a trailing point or `-0`:
/// `format_number(-0.0004, 3) == "0"`, `format_number(12.5, 3) == "12.5"`.
/// Non-finite input prints as "0" (callers reject non-finite values before formatting).
///
/// The digits are those of the exact binary value of `v` rounded to `decimals` places, as
/// `format!("{:.*}", decimals, v)` gives them, but computed in integer arithmetic where that
/// is provably the same (`rounded_scaled`); otherwise (ties, huge values, many decimals)
/// by `format!`.
#[must_use]
pub fn format_number(v: f64, decimals: u32) -> String {
    let mut s = String::new();
    push_number(&mut s, v, decimals);
    s
}

/// [`format_number`] appended to `out`: no allocation on the integer route.
pub fn push_number(out: &mut String, v: f64, decimals: u32) {
    if !v.is_finite() {
        out.push('0');
        return;
    }
    match rounded_scaled(v.abs(), decimals) {
        Some(n) => push_digits_of_scaled(out, v < 0.0, n, decimals),
        None => out.push_str(&format_number_std(v, decimals)),
    }
}

/// Most decimals of the integer route: 10^`decimals` must be exact in `f64` and leave
/// room below 2⁵³ for the integer part.
const FAST_DECIMALS: u32 = 9;

/// 10^d for d ≤ [`FAST_DECIMALS`], each exact in `f64` (the values `powi` gives, without
/// a call per number).
const POW10: [f64; FAST_DECIMALS as usize + 1] = [1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// 10^`d` (exact for d ≤ 22): from [`POW10`] where it reaches, else by `powi`.
pub fn pow10(d: u32) -> f64 {
    POW10
        .get(d as usize)
        .copied()
        .unwrap_or_else(|| 10f64.powi(d as i32))
}

/// The same powers as integers, for splitting a scaled value into its integer part and
/// fraction digits.
const POW10_U64: [u64; FAST_DECIMALS as usize + 1] = [
    1,
    10,
    100,
    1_000,
    10_000,
    100_000,
    1_000_000,
    10_000_000,
    100_000_000,
    1_000_000_000,
];

/// `a` (≥ 0, finite) times 10^`decimals`, rounded to the nearest integer, when the product
/// computed in floating point decides that rounding. 10^d is exact for d ≤ 22, so
/// p = fl(a·10^d) is the exact product x rounded once. Below 2⁵² every k + ½ is an `f64`,
/// and rounding is monotone, so x < k + ½ gives p ≤ k + ½ and x > k + ½ gives p ≥ k + ½:
/// where p's fraction is not exactly ½, x rounds to the same integer as p. Where it is ½
/// (x a tie, which `format!` breaks to even, or within half an ulp of one), for p ≥ 2⁵²,
/// or for d > [`FAST_DECIMALS`]: `None`.
pub(super) fn rounded_scaled(a: f64, decimals: u32) -> Option<u64> {
    if decimals > FAST_DECIMALS {
        return None;
    }
    let p = a * POW10[decimals as usize];
    // 2⁵² (a is finite and ≥ 0, so p is not NaN).
    if p >= 4_503_599_627_370_496.0 {
        return None;
    }
    let floor = p.floor();
    let frac = p - floor; // exact (Sterbenz)
    if frac == 0.5 {
        return None;
    }
    Some(floor as u64 + u64::from(frac > 0.5))
}

/// The text of ±n/10^`decimals` without trailing zeros, a trailing point or `-0`: the
/// integer part and the fraction (after the trailing zeros are divided out) as decimal
/// integers by `itoa`, the fraction's leading zeros kept by formatting it plus
/// 10^places and dropping that leading 1.
fn push_digits_of_scaled(out: &mut String, negative: bool, n: u64, decimals: u32) {
    let mut rest = n;
    let mut places = decimals as usize;
    while places > 0 && rest.is_multiple_of(10) {
        rest /= 10;
        places -= 1;
    }
    let scale = POW10_U64[places];
    if negative && n != 0 {
        out.push('-');
    }
    let mut digits = itoa::Buffer::new();
    out.push_str(digits.format(rest / scale));
    if places > 0 {
        out.push('.');
        let fraction = digits.format(rest % scale + scale);
        out.push_str(&fraction[1..]);
    }
}

/// [`format_number`] by the standard formatter alone, `format!("{:.*}")` (exact decimal
/// expansion of the binary value, ties to even), then trimmed: its fallback, and the
/// reference its integer route is tested and benchmarked against.
#[must_use]
pub fn format_number_std(v: f64, decimals: u32) -> String {
    let mut s = format!("{:.*}", decimals as usize, v);
    if s.contains('.') {
        while s.ends_with('0') {
            s.pop();
        }
        if s.ends_with('.') {
            s.pop();
        }
    }
    if s == "-0" || s.is_empty() {
        s = "0".to_string();
    }
    s
}
