//! The agreement that keeps a failing process from leaving the others waiting: after each
//! step that can fail on one process alone (a file, the device, writing), every process learns
//! the lowest failing rank before any waits on another, and all stop together.

use mpi::collective::SystemOperation;
use mpi::topology::Rank;
use mpi::traits::*;

use crate::error::{Error, Result};

/// `local` where every process of `comm` succeeded; else this process's own error, or
/// [`Error::OtherRank`] naming the lowest failing rank. Collective.
pub fn agree<T, C: Communicator>(comm: &C, local: Result<T>) -> Result<T> {
    let failed = match &local {
        Ok(_) => Rank::MAX,
        Err(_) => comm.rank(),
    };
    let mut first = Rank::MAX;
    comm.all_reduce_into(&failed, &mut first, SystemOperation::min());
    match local {
        Err(e) => Err(e),
        Ok(_) if first != Rank::MAX => Err(Error::OtherRank { rank: first }),
        Ok(value) => Ok(value),
    }
}
