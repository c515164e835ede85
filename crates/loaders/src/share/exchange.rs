//! What reading a share of a file needs from the processes reading the others: each one's
//! place, gathering every process's few numbers, and sending each process a list of its own.
//! The loaders link no message-passing library: the host implements [`Exchange`] over its own
//! (the `ellipsoid-splat-mpi` binary over an MPI communicator, the tests over threads).

/// The processes that read one file together, each its own share
/// ([`load_share`](crate::load_share)).
///
/// Both operations are collective: every process calls them, the same number of times in the
/// same order. An `Err` must come on every process alike (or on none), so that no process goes
/// on to the next exchange while another has stopped: the loaders return it as their error.
pub trait Exchange {
    /// This process's place among them, from 0 to `size() - 1`.
    fn rank(&self) -> usize;

    /// How many processes read the file.
    fn size(&self) -> usize;

    /// Every process's `mine`, in rank order (each may give a different length).
    fn all_gather(&self, mine: &[u64]) -> Result<Vec<Vec<u64>>, String>;

    /// Sends `send[r]` to rank `r` (one list per rank) and returns what each rank sent this
    /// one, in rank order.
    fn all_to_all(&self, send: &[Vec<u64>]) -> Result<Vec<Vec<u64>>, String>;
}
