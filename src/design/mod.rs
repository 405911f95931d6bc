//! The design file model (format v1, TOML or JSON), its validation, and import.
