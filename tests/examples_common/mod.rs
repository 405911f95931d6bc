//! The shipped examples (examples/*.toml), one list for every integration test that runs
//! them all. `every_example_is_listed` keeps it in step with the folder.

/// The names of the shipped example designs, without `.toml`.
pub const EXAMPLES: [&str; 9] = [
    "brush",
    "calligraphy",
    "circles",
    "gclef",
    "loop",
    "neon_word",
    "ring_o",
    "seahorse",
    "snake",
];
