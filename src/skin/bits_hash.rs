//! A fast hasher for keys made of float bit patterns, and the maps that use it.

use std::collections::{HashMap, HashSet};

/// Hasher of keys made of float bit patterns (the bound cache keys of the skinning, curve
/// parameters, parameter intervals), mixed a word at a time by rotate, xor and an odd
/// multiplier (the FxHash scheme). The keys are our own numbers, not an adversary's, so
/// the DoS resistance (and cost) of the standard SipHash buys nothing here; the maps are only looked up, never iterated, so the hasher cannot change a
/// result.
#[derive(Clone, Copy, Default)]
pub struct KeyHasher(u64);

impl std::hash::Hasher for KeyHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write_u64(&mut self, x: u64) {
        /// 2⁶⁴/φ rounded to odd: consecutive inputs spread over all bits.
        const K: u64 = 0x9e37_79b9_7f4a_7c15;
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(K);
    }
    fn write(&mut self, bytes: &[u8]) {
        for chunk in bytes.chunks(8) {
            let mut w = [0u8; 8];
            w[..chunk.len()].copy_from_slice(chunk);
            self.write_u64(u64::from_le_bytes(w));
        }
    }
    fn write_usize(&mut self, x: usize) {
        self.write_u64(x as u64);
    }
}

/// Maps hashed by [`KeyHasher`].
pub type BitsMap<K, V> = HashMap<K, V, std::hash::BuildHasherDefault<KeyHasher>>;

/// Sets hashed by [`KeyHasher`].
pub type BitsSet<K> = HashSet<K, std::hash::BuildHasherDefault<KeyHasher>>;
