//! Owen-scrambled Sobol points four dimensions at a time: the numbers of
//! `sobol_burley::sample_4d` (Burley 2020), bit for bit, computed faster.
//!
//! The crate multiplies the sample index into the Sobol generator matrices bit by bit, a loop
//! whose trip count is the number of set bits in the shuffled index, so it varies at random
//! from call to call and its exit is mispredicted about once per call. The product is linear
//! over XOR, so it splits into four 4-bit pieces of the (16-bit) index: a table per dimension
//! set holds the product of each piece's 16 values, and a point is four lookups and three
//! XORs (1 KiB per set of four dimensions; the first few sets, which every path uses, stay in
//! the L1 cache). The index shuffle and the output scramble are the crate's own functions.

use std::sync::OnceLock;

use sobol_burley::parts::{hash, hash_int4, owen_scramble_int4_rev, owen_scramble_rev, sobol_int4_rev, Int4};
use sobol_burley::NUM_DIMENSION_SETS_4D;

/// Sets of four dimensions the tables cover (the crate's maximum, 256 dimensions).
pub const SETS: u32 = NUM_DIMENSION_SETS_4D;

/// `products[set][piece][value]`: the generator matrices of `set` times the index whose
/// reversed bits are `value` in 4-bit piece `piece` (counted from the top) and zero elsewhere.
struct Tables {
    products: Vec<[[Int4; 16]; 4]>,
}

fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(|| Tables {
        products: (0..SETS)
            .map(|set| {
                std::array::from_fn(|piece| {
                    std::array::from_fn(|value| sobol_int4_rev((value as u32) << (28 - 4 * piece), set))
                })
            })
            .collect(),
    })
}

/// Sample `index`'s shuffled position in the scrambled sequence of `seed`, bits reversed: what
/// every dimension set of one sample shares (compute it once per sample).
#[inline]
pub fn shuffled_index(index: u32, seed: u32) -> u32 {
    debug_assert!(index < 1 << 16);
    owen_scramble_rev(index.reverse_bits(), hash(seed ^ 0x79c68e4a))
}

/// Dimensions `4 set .. 4 set + 4` of the sample whose shuffled index is `shuffled` (from
/// `shuffled_index` with the same `seed`), each in [0, 1): `sobol_burley::sample_4d(index,
/// set, seed)`.
#[inline]
pub fn sample_4d(shuffled: u32, set: u32, seed: u32) -> [f32; 4] {
    let pieces = &tables().products[set as usize];
    let sobol = pieces[0][(shuffled >> 28) as usize]
        ^ pieces[1][(shuffled >> 24 & 15) as usize]
        ^ pieces[2][(shuffled >> 20 & 15) as usize]
        ^ pieces[3][(shuffled >> 16 & 15) as usize];
    // The crate's scramble, unchanged: a per-set, per-lane Owen scramble of the bits.
    let scramble = {
        let seed: Int4 = [seed.wrapping_mul(0x9c8f2d3b); 4].into();
        let set: Int4 = [set; 4].into();
        seed ^ set ^ [0x912f69ba, 0x174f18ab, 0x691e72ca, 0xb40cc1b8].into()
    };
    owen_scramble_int4_rev(sobol, hash_int4(scramble)).reverse_bits().to_f32_norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same numbers as the crate, bit for bit, over every dimension set, indices spread
    /// over the whole 16-bit range and several seeds.
    #[test]
    fn equals_the_crate() {
        let mut checked = 0;
        for seed in [0u32, 1, 0x5eed, 0xdead_beef, u32::MAX] {
            for index in (0..1u32 << 16).step_by(97).chain([0, 1, 2, 3, 0xFFFF]) {
                let shuffled = shuffled_index(index, seed);
                for set in 0..SETS {
                    let ours = sample_4d(shuffled, set, seed).map(f32::to_bits);
                    let theirs = sobol_burley::sample_4d(index, set, seed).map(f32::to_bits);
                    assert_eq!(ours, theirs, "index {index}, set {set}, seed {seed}");
                    checked += 1;
                }
            }
        }
        assert!(checked > 100_000);
    }
}
