//! Machine profiles (machines/*.toml) and G-code dialects.
