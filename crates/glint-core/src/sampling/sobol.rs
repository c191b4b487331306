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
use wide::{f32x8, u32x8};

/// Sets of four dimensions the tables cover (the crate's maximum, 256 dimensions).
pub const SETS: u32 = NUM_DIMENSION_SETS_4D;

/// `products[set][piece][value]`: the generator matrices of `set` times the index whose
/// reversed bits are `value` in 4-bit piece `piece` (counted from the top) and zero elsewhere.
struct Tables {
    products: Vec<[[[u32; 4]; 16]; 4]>,
}

fn tables() -> &'static Tables {
    static TABLES: OnceLock<Tables> = OnceLock::new();
    TABLES.get_or_init(|| Tables {
        products: (0..SETS)
            .map(|set| {
                std::array::from_fn(|piece| {
                    std::array::from_fn(|value| sobol_int4_rev((value as u32) << (28 - 4 * piece), set).into())
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

/// `shuffled_index` of one sample index under eight seeds at once (eight pixels' samples of
/// one pass), the crate's hash and scramble in lanes.
pub fn shuffled_index_lanes(index: u32, seed: [u32; 8]) -> [u32; 8] {
    debug_assert!(index < 1 << 16);
    let scramble = hash8(u32x8::from(seed) ^ u32x8::splat(0x79c68e4a));
    owen_scramble_rev8(u32x8::splat(index.reverse_bits()), scramble).to_array()
}

/// Dimensions `4 set .. 4 set + 4` of the sample whose shuffled index is `shuffled` (from
/// `shuffled_index` with the same `seed`), each in [0, 1): `sobol_burley::sample_4d(index,
/// set, seed)`.
#[inline]
pub fn sample_4d(shuffled: u32, set: u32, seed: u32) -> [f32; 4] {
    let sobol = Int4::from(sobol_set_rev(set_tables(set), shuffled));
    // The crate's scramble, unchanged: a per-set, per-lane Owen scramble of the bits.
    let scramble = {
        let seed: Int4 = [seed.wrapping_mul(0x9c8f2d3b); 4].into();
        let set: Int4 = [set; 4].into();
        seed ^ set ^ [0x912f69ba, 0x174f18ab, 0x691e72ca, 0xb40cc1b8].into()
    };
    owen_scramble_int4_rev(sobol, hash_int4(scramble)).reverse_bits().to_f32_norm()
}

/// The tables of dimensions `4 set .. 4 set + 4`.
#[inline(always)]
fn set_tables(set: u32) -> &'static [[[u32; 4]; 16]; 4] {
    &tables().products[set as usize]
}

/// The Sobol point (not yet scrambled, bits reversed) of the dimensions of `pieces` (a set's
/// tables) at the shuffled index: four table lookups, XORed.
#[inline(always)]
fn sobol_set_rev(pieces: &[[[u32; 4]; 16]; 4], shuffled: u32) -> [u32; 4] {
    let [a, b, c, d] = [
        pieces[0][(shuffled >> 28) as usize],
        pieces[1][(shuffled >> 24 & 15) as usize],
        pieces[2][(shuffled >> 20 & 15) as usize],
        pieces[3][(shuffled >> 16 & 15) as usize],
    ];
    std::array::from_fn(|i| a[i] ^ b[i] ^ c[i] ^ d[i])
}

/// `sample_4d` for eight samples at once, the same `set` for all and each its own shuffled
/// index and seed: the same bits, both as one vector per dimension and per sample. The crate's
/// scramble is a chain of dependent multiplies and shifts on four lanes; here each step runs
/// on two samples' four dimensions at once, half the instructions. For samples that stand at
/// the same dimension: a tile's camera jitter, the path tracer's wavefront.
pub fn sample_4d_lanes(shuffled: [u32; 8], set: u32, seed: [u32; 8]) -> Sets8 {
    let pieces = set_tables(set);
    let sobol = shuffled.map(|s| sobol_set_rev(pieces, s));
    // The crate's per-dimension scramble constants, for both samples of a pair.
    let [c0, c1, c2, c3] = [0x912f69ba, 0x174f18ab, 0x691e72ca, 0xb40cc1b8];
    let constants = u32x8::from([c0, c1, c2, c3, c0, c1, c2, c3]) ^ u32x8::splat(set);
    // Pair j holds samples j and j + 4: the transpose below then puts the samples in order.
    let pairs: [[f32; 8]; 4] = std::array::from_fn(|j| {
        let (a, b) = (j, j + 4);
        let sobol = u32x8::from([
            sobol[a][0],
            sobol[a][1],
            sobol[a][2],
            sobol[a][3],
            sobol[b][0],
            sobol[b][1],
            sobol[b][2],
            sobol[b][3],
        ]);
        let seeds = u32x8::from([seed[a], seed[a], seed[a], seed[a], seed[b], seed[b], seed[b], seed[b]]);
        let scramble = (seeds * u32x8::splat(0x9c8f2d3b)) ^ constants;
        let bits = reverse_bits(owen_scramble_rev8(sobol, hash8(scramble)));
        // The crate's `to_f32_norm`: the top 23 bits as the mantissa of a float in [1, 2).
        let values: f32x8 = bytemuck::cast((bits >> 9) | u32x8::splat(0x3f80_0000));
        (values - f32x8::ONE).to_array()
    });
    let p = &pairs;
    Sets8 {
        by_dimension: std::array::from_fn(|i| {
            f32x8::from([p[0][i], p[1][i], p[2][i], p[3][i], p[0][4 + i], p[1][4 + i], p[2][4 + i], p[3][4 + i]])
        }),
        by_sample: std::array::from_fn(|k| {
            let half = 4 * (k / 4);
            [p[k % 4][half], p[k % 4][half + 1], p[k % 4][half + 2], p[k % 4][half + 3]]
        }),
    }
}

/// One set of four dimensions of eight samples (`sample_4d_lanes`).
pub struct Sets8 {
    /// Lane k of `by_dimension[i]`: dimension i of sample k.
    pub by_dimension: [f32x8; 4],
    /// The four dimensions of sample k.
    pub by_sample: [[f32; 4]; 8],
}

/// The crate's `hash_int4`, eight wide.
#[inline(always)]
fn hash8(mut n: u32x8) -> u32x8 {
    n ^= u32x8::splat(0xe6fe3beb);
    n ^= n >> 16;
    n = n * u32x8::splat(0x7feb352d);
    n ^= n >> 15;
    n = n * u32x8::splat(0x846ca68b);
    n ^ (n >> 16)
}

/// The crate's `owen_scramble_int4_rev`, eight wide.
#[inline(always)]
fn owen_scramble_rev8(mut n: u32x8, scramble: u32x8) -> u32x8 {
    n ^= n * u32x8::splat(0x3d20adea);
    n += scramble;
    n = n * ((scramble >> 16) | u32x8::splat(1));
    n ^= n * u32x8::splat(0x05526c56);
    n ^ (n * u32x8::splat(0x53a22864))
}

/// `u32::reverse_bits` in each lane.
#[inline(always)]
fn reverse_bits(mut n: u32x8) -> u32x8 {
    for (shift, mask) in [(1, 0x5555_5555u32), (2, 0x3333_3333), (4, 0x0f0f_0f0f), (8, 0x00ff_00ff)] {
        let mask = u32x8::splat(mask);
        n = ((n >> shift) & mask) | ((n & mask) << shift);
    }
    (n >> 16) | (n << 16)
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

    /// Eight shuffled indices at once equal eight calls.
    #[test]
    fn eight_shuffled_indices_equal_one_at_a_time() {
        for round in 0..500u32 {
            let seed: [u32; 8] = std::array::from_fn(|k| (round * 8 + k as u32).wrapping_mul(0x9E37_79B9) ^ 0x5eed);
            let index = round.wrapping_mul(2_654_435_761) >> 16;
            assert_eq!(shuffled_index_lanes(index, seed), seed.map(|s| shuffled_index(index, s)), "round {round}");
        }
    }

    /// Eight samples at once equal eight calls, bit for bit.
    #[test]
    fn eight_at_once_equal_one_at_a_time() {
        let mut checked = 0;
        for round in 0..200u32 {
            let seed: [u32; 8] = std::array::from_fn(|k| (round * 8 + k as u32).wrapping_mul(0x9E37_79B9) ^ 0x5eed);
            let index: [u32; 8] = std::array::from_fn(|k| (round * 331 + k as u32 * 4099) & 0xFFFF);
            let shuffled: [u32; 8] = std::array::from_fn(|k| shuffled_index(index[k], seed[k]));
            for set in [0, 1, 2, round % SETS, SETS - 1] {
                let sets = sample_4d_lanes(shuffled, set, seed);
                let lanes = sets.by_dimension.map(|d| d.to_array());
                for k in 0..8 {
                    let one = sample_4d(shuffled[k], set, seed[k]).map(f32::to_bits);
                    let got = [0, 1, 2, 3].map(|i| lanes[i][k].to_bits());
                    assert_eq!(got, one, "sample {k}, set {set}, round {round}, by dimension");
                    assert_eq!(sets.by_sample[k].map(f32::to_bits), one, "sample {k}, set {set}, round {round}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 200 * 5 * 8);
    }
}
