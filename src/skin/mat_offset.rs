//! MAT offsets of RE skins (in progress).
