//! Mutations of seed inputs: the classic ones of AFL and libFuzzer, without their coverage
//! feedback.

/// SplitMix64: a small, fast, seedable generator.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed ^ 0x9E37_79B9_7F4A_7C15)
    }

    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in 0..n (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// Numbers at the edges of what readers expect.
const BOUNDARY: &[&str] = &[
    "0",
    "-1",
    "1e38",
    "-1e38",
    "1e-45",
    "nan",
    "inf",
    "-inf",
    "4294967295",
    "4294967296",
    "2147483648",
    "-2147483649",
    "1e309",
    "0.0",
    "-0",
    "65535",
    "99999999999999999999",
];

/// One input: a seed (or two, spliced) changed by one to eight mutations.
pub fn mutate(rng: &mut Rng, corpus: &[Vec<u8>], tokens: &[&str]) -> Vec<u8> {
    let mut data = corpus[rng.below(corpus.len())].clone();
    for _ in 0..1 + rng.below(8) {
        let len = data.len();
        match rng.below(11) {
            // Flip a bit.
            0 if len > 0 => {
                let i = rng.below(len);
                data[i] ^= 1 << rng.below(8);
            }
            // Set a byte to anything.
            1 if len > 0 => {
                let i = rng.below(len);
                data[i] = rng.next() as u8;
            }
            // Delete a block.
            2 if len > 1 => {
                let i = rng.below(len);
                let n = 1 + rng.below((len - i).min(64));
                data.drain(i..i + n);
            }
            // Duplicate a block in place (repeats, deeper nesting).
            3 if len > 1 => {
                let i = rng.below(len);
                let n = 1 + rng.below((len - i).min(256));
                let block: Vec<u8> = data[i..i + n].to_vec();
                for _ in 0..1 + rng.below(4) {
                    data.splice(i..i, block.iter().copied());
                }
            }
            // A boundary number over a run of digits, or inserted.
            4 => {
                let number = BOUNDARY[rng.below(BOUNDARY.len())].as_bytes();
                replace_number(rng, &mut data, number);
            }
            // One of the format's tokens, inserted.
            5 if !tokens.is_empty() => {
                let token = tokens[rng.below(tokens.len())].as_bytes();
                let i = rng.below(len + 1);
                data.splice(i..i, token.iter().copied());
            }
            // Splice: this input's head with another seed's tail.
            6 => {
                let other = &corpus[rng.below(corpus.len())];
                let (i, j) = (rng.below(len + 1), rng.below(other.len() + 1));
                data.truncate(i);
                data.extend_from_slice(&other[j..]);
            }
            // Cut the input short.
            7 if len > 0 => data.truncate(rng.below(len)),
            // A 32-bit little-endian boundary value over four bytes (binary formats' headers).
            8 if len >= 4 => {
                let i = rng.below(len - 3);
                let values = [0u32, 1, 0xFFFF_FFFF, 0x8000_0000, 1 << 30, 0x7F80_0000, 0x7FC0_0000, 0xFF80_0000];
                data[i..i + 4].copy_from_slice(&values[rng.below(values.len())].to_le_bytes());
            }
            // Swap two bytes.
            9 if len > 1 => {
                let (i, j) = (rng.below(len), rng.below(len));
                data.swap(i, j);
            }
            // Increment or decrement a byte (an ASCII digit now and then).
            _ if len > 0 => {
                let i = rng.below(len);
                data[i] = if rng.below(2) == 0 { data[i].wrapping_add(1) } else { data[i].wrapping_sub(1) };
            }
            _ => {}
        }
        // Bounded so that a run cannot grow its inputs without end.
        data.truncate(1 << 20);
    }
    data
}

/// Replaces a run of digits (with sign, point and exponent) by `number`, or inserts it.
fn replace_number(rng: &mut Rng, data: &mut Vec<u8>, number: &[u8]) {
    let is_numeric = |b: u8| b.is_ascii_digit() || b == b'.' || b == b'-' || b == b'e';
    let starts: Vec<usize> =
        (0..data.len()).filter(|&i| data[i].is_ascii_digit() && (i == 0 || !is_numeric(data[i - 1]))).collect();
    if starts.is_empty() {
        let i = rng.below(data.len() + 1);
        data.splice(i..i, number.iter().copied());
        return;
    }
    let start = starts[rng.below(starts.len())];
    let end = (start..data.len()).find(|&i| !is_numeric(data[i])).unwrap_or(data.len());
    data.splice(start..end, number.iter().copied());
}
