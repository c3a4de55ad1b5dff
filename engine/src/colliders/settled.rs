//! A chunk's settled lanes, as the in-step pass keeps them: one byte a
//! block of four, a lane's bit set once it is settled (clear of every
//! in-step collider, resting on it, or followed), `0b1111` a block whose
//! lanes are all settled; and the blocks still open, as bits.

use crate::layout::CHUNK;

/// The blocks of `settled` (each block's settled lanes, four bits a byte)
/// with a lane not settled, as bits, eight bytes at a time without a
/// branch a byte: a byte `ALL` (`0b1111`) XOR `ALL` is 0, any other has
/// one of its low four bits set, which is folded into its lowest bit and
/// the eight lowest bits gathered by one multiplication.
pub(crate) fn open_blocks(settled: &[u8]) -> [u64; (CHUNK / 4).div_ceil(64)] {
    const ALL: u64 = u64::from_ne_bytes([0b1111; 8]);
    const LOW: u64 = u64::from_le_bytes([1; 8]);
    let mut open = [0u64; (CHUNK / 4).div_ceil(64)];
    for (k, bytes) in settled.chunks(8).enumerate() {
        let eight = match <[u8; 8]>::try_from(bytes) {
            Ok(eight) => u64::from_le_bytes(eight),
            Err(_) => bytes.iter().rev().fold(ALL, |word, &byte| word << 8 | u64::from(byte)),
        };
        let t = eight ^ ALL;
        let any = (t | t >> 1 | t >> 2 | t >> 3) & LOW;
        // Byte i's bit (at 8 i) to bit 56 + i: no two products overlap.
        let bits = any.wrapping_mul(0x0102_0408_1020_4080) >> 56;
        open[k / 8] |= bits << (k % 8 * 8);
    }
    open
}

/// Calls `f` with the index of each set bit of `words`, in order.
#[inline(always)]
pub(crate) fn for_each_bit(words: &[u64], mut f: impl FnMut(usize)) {
    for (word, &bits) in words.iter().enumerate() {
        let mut bits = bits;
        while bits != 0 {
            f(word * 64 + bits.trailing_zeros() as usize);
            bits &= bits - 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The open blocks found eight bytes at a time are those whose byte is
    /// not `0b1111`, whatever the bytes and the chunk's length.
    #[test]
    fn open_blocks_are_the_bytes_not_all_settled() {
        let mut seed = 0x9e37_79b9_u32;
        for case in 0..2_000 {
            let len = 1 + case % (CHUNK / 4);
            let settled: Vec<u8> = (0..len)
                .map(|_| {
                    seed ^= seed << 13;
                    seed ^= seed >> 17;
                    seed ^= seed << 5;
                    // Mostly settled, as in a crowd.
                    if seed.is_multiple_of(3) {
                        (seed >> 8) as u8 & 0b1111
                    } else {
                        0b1111
                    }
                })
                .collect();
            let open = open_blocks(&settled);
            for b in 0..CHUNK / 4 {
                let expected = b < len && settled[b] != 0b1111;
                assert_eq!(open[b / 64] >> (b % 64) & 1 == 1, expected, "case {case}, block {b}");
            }
        }
    }
}
