//! Helpers shared by the readers' integration tests.

/// `count` corrupted copies of `original`, deterministic in `seed`: each has one to four
/// edits, a run of bytes deleted or duplicated, a byte replaced by one of `specials` (the
/// format's syntax), or the file cut short.
pub fn mutants(original: &[u8], specials: &[u8], count: usize, seed: u64) -> Vec<Vec<u8>> {
    let mut state = seed;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    (0..count)
        .map(|_| {
            let mut bytes = original.to_vec();
            for _ in 0..1 + next(4) {
                let i = next(bytes.len());
                match next(4) {
                    0 => {
                        let end = (i + 1 + next(12)).min(bytes.len());
                        bytes.drain(i..end);
                    }
                    1 => {
                        let end = (i + 1 + next(12)).min(bytes.len());
                        let copy = bytes[i..end].to_vec();
                        bytes.splice(i..i, copy);
                    }
                    2 => bytes[i] = specials[next(specials.len())],
                    _ => bytes.truncate(i),
                }
                if bytes.is_empty() {
                    break;
                }
            }
            bytes
        })
        .collect()
}
