//! Every process learning whether any failed, before any of them waits on another: a process
//! that stops alone would leave the others waiting for its image.

use mpi::collective::SystemOperation;
use mpi::topology::Rank;
use mpi::traits::*;

/// The lowest rank of `comm` whose `failed` is true, or `None` when none failed. Collective:
/// every process of `comm` calls it, failed or not, at the same point (one all-reduce).
pub fn first_failed<C: Communicator>(comm: &C, failed: bool) -> Option<Rank> {
    let mine = if failed { comm.rank() } else { Rank::MAX };
    let mut first = Rank::MAX;
    comm.all_reduce_into(&mine, &mut first, SystemOperation::min());
    (first != Rank::MAX).then_some(first)
}
