//! Binary-swap compositing, as design §6.3 of the repository's `docs/design.md` describes it
//! (the rounds, the partners, what each process sends): every process ends with an equal slice
//! of the combined image. A pixel keeps the smaller key ([`pixels::merge`]), so the result is
//! exact whatever the order of the merges.

use std::ops::Range;

use mpi::point_to_point as p2p;
use mpi::topology::Rank;
use mpi::traits::*;

use crate::pixels::{self, WORDS};

/// What one process sent while compositing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Traffic {
    /// Bytes sent.
    pub bytes: u64,
    /// Messages sent.
    pub messages: u32,
}

/// The largest power of two not above `size` (at least 1).
fn swapping(size: Rank) -> Rank {
    let mut q = 1;
    while q * 2 <= size {
        q *= 2;
    }
    q
}

/// The range of pixels (of `pixels`) that swapping process `rank` of `q` holds after the
/// rounds: the halves its bits chose, highest bit first.
pub fn slice_of(rank: Rank, q: Rank, pixels: usize) -> Range<usize> {
    let mut range = 0..pixels;
    let mut bit = q / 2;
    while bit >= 1 {
        let middle = range.start + (range.end - range.start) / 2;
        range = if rank & bit == 0 {
            range.start..middle
        } else {
            middle..range.end
        };
        bit /= 2;
    }
    range
}

/// Combines every process's `words` (each a whole image of `pixels` pixels, [`pixels::encode`])
/// over `comm`; returns the range of pixels this process ends with and their combined words
/// (an empty range on the extra processes), and what it sent.
pub fn composite<C: Communicator>(
    comm: &C,
    mut words: Vec<u64>,
    pixels: usize,
) -> (Range<usize>, Vec<u64>, Traffic) {
    let (rank, size) = (comm.rank(), comm.size());
    let q = swapping(size);
    let mut traffic = Traffic::default();
    let mut sent = |count: usize| {
        traffic.bytes += (count * 8) as u64;
        traffic.messages += 1;
    };
    // The extra processes fold into the first q.
    if rank >= q {
        comm.process_at_rank(rank - q).send(&words[..]);
        sent(words.len());
        return (0..0, Vec::new(), traffic);
    }
    if rank + q < size {
        let mut theirs = vec![0u64; words.len()];
        comm.process_at_rank(rank + q).receive_into(&mut theirs[..]);
        pixels::merge(&mut words, &theirs);
    }
    // The range held shrinks in place: `words` stays the whole image's buffer, the received
    // half lands in one buffer made once, and merging writes into the kept half.
    let mut range = 0..pixels;
    let mut theirs = vec![0u64; pixels.div_ceil(2) * WORDS];
    let mut bit = q / 2;
    while bit >= 1 {
        let partner = comm.process_at_rank(rank ^ bit);
        let middle = range.start + (range.end - range.start) / 2;
        let (keep, give) = if rank & bit == 0 {
            (range.start..middle, middle..range.end)
        } else {
            (middle..range.end, range.start..middle)
        };
        let words_of = |r: &Range<usize>| r.start * WORDS..r.end * WORDS;
        let received = &mut theirs[..(keep.end - keep.start) * WORDS];
        p2p::send_receive_into(&words[words_of(&give)], &partner, &mut *received, &partner);
        sent((give.end - give.start) * WORDS);
        pixels::merge(&mut words[words_of(&keep)], received);
        range = keep;
        bit /= 2;
    }
    let words = words[range.start * WORDS..range.end * WORDS].to_vec();
    (range, words, traffic)
}

/// The whole combined image at `root` (`Some` there, `None` elsewhere): each swapping
/// process sends its slice (`words`, as [`composite`] left it), the root places them.
pub fn gather<C: Communicator>(
    comm: &C,
    root: Rank,
    words: Vec<u64>,
    pixels: usize,
    traffic: &mut Traffic,
) -> Option<Vec<u64>> {
    let (rank, q) = (comm.rank(), swapping(comm.size()));
    if rank != root {
        if rank < q {
            comm.process_at_rank(root).send(&words[..]);
            traffic.bytes += (words.len() * 8) as u64;
            traffic.messages += 1;
        }
        return None;
    }
    let mut image = vec![0u64; pixels * WORDS];
    for from in 0..q {
        let slice = slice_of(from, q, pixels);
        let into = &mut image[slice.start * WORDS..slice.end * WORDS];
        if from == rank {
            into.copy_from_slice(&words);
        } else {
            comm.process_at_rank(from).receive_into(into);
        }
    }
    Some(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slices_tile_the_image() {
        for q in [1, 2, 4, 8, 16] {
            for pixels in [0, 1, 7, 1000, 1921 * 1081] {
                let mut covered = vec![0u8; pixels];
                for rank in 0..q {
                    for p in slice_of(rank, q, pixels) {
                        covered[p] += 1;
                    }
                }
                assert!(covered.iter().all(|&c| c == 1), "q {q}, {pixels} pixels");
            }
        }
        assert_eq!(swapping(1), 1);
        assert_eq!(swapping(3), 2);
        assert_eq!(swapping(8), 8);
        assert_eq!(swapping(13), 8);
    }
}
