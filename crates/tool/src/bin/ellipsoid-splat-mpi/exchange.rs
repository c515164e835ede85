//! The loaders' [`Exchange`] over an MPI communicator: what reading the shares of a file needs
//! (gathering every process's numbers, sending each its own list) as MPI's variable-count
//! all-gather and all-to-all. MPI counts are `int`: a list too long for one fails every
//! process alike (the sizes are exchanged first), never one alone.

use mpi::collective::SystemOperation;
use mpi::datatype::{Partition, PartitionMut};
use mpi::traits::*;
use mpi::Count;

use ellipsoid_splat_loaders::Exchange;

/// The processes of `comm`.
pub struct MpiExchange<'a, C: Communicator> {
    comm: &'a C,
}

impl<'a, C: Communicator> MpiExchange<'a, C> {
    pub fn new(comm: &'a C) -> Self {
        Self { comm }
    }
}

/// `counts` as MPI counts with their displacements, or why they do not fit an `int`.
fn partition(counts: &[u64]) -> Result<(Vec<Count>, Vec<Count>), String> {
    let total: u64 = counts.iter().sum();
    if total > Count::MAX as u64 {
        return Err(format!(
            "{total} words in one exchange: more than MPI's counts ({}) reach",
            Count::MAX
        ));
    }
    let counts: Vec<Count> = counts.iter().map(|&c| c as Count).collect();
    let displs = counts
        .iter()
        .scan(0, |at, &c| {
            let here = *at;
            *at += c;
            Some(here)
        })
        .collect();
    Ok((counts, displs))
}

/// `words` cut into consecutive lists of `counts`.
fn split(words: Vec<u64>, counts: &[Count]) -> Vec<Vec<u64>> {
    let mut rest = words.as_slice();
    counts
        .iter()
        .map(|&c| {
            let (list, tail) = rest.split_at(c as usize);
            rest = tail;
            list.to_vec()
        })
        .collect()
}

impl<C: Communicator> Exchange for MpiExchange<'_, C> {
    fn rank(&self) -> usize {
        self.comm.rank() as usize
    }

    fn size(&self) -> usize {
        self.comm.size() as usize
    }

    fn all_gather(&self, mine: &[u64]) -> Result<Vec<Vec<u64>>, String> {
        let mut lengths = vec![0u64; self.size()];
        self.comm
            .all_gather_into(&(mine.len() as u64), &mut lengths[..]);
        // Every process has every length: all fail alike.
        let (counts, displs) = partition(&lengths)?;
        let mut words = vec![0u64; lengths.iter().sum::<u64>() as usize];
        {
            let mut into = PartitionMut::new(&mut words[..], &counts[..], &displs[..]);
            self.comm.all_gather_varcount_into(mine, &mut into);
        }
        Ok(split(words, &counts))
    }

    fn all_to_all(&self, send: &[Vec<u64>]) -> Result<Vec<Vec<u64>>, String> {
        if send.len() != self.size() {
            // The same on every process only if every caller errs alike: the loaders always
            // give one list per process.
            return Err(format!(
                "{} lists for {} processes",
                send.len(),
                self.size()
            ));
        }
        let sending: Vec<u64> = send.iter().map(|l| l.len() as u64).collect();
        let mut receiving = vec![0u64; self.size()];
        self.comm.all_to_all_into(&sending[..], &mut receiving[..]);
        let sizes = (partition(&sending), partition(&receiving));
        // A process whose lists do not fit an `int` makes every process stop.
        let fits = u8::from(sizes.0.is_ok() && sizes.1.is_ok());
        let mut all_fit = 0u8;
        self.comm
            .all_reduce_into(&fits, &mut all_fit, SystemOperation::min());
        let ((send_counts, send_displs), (counts, displs)) = match sizes {
            (Ok(s), Ok(r)) if all_fit == 1 => (s, r),
            (Err(e), _) | (_, Err(e)) => return Err(e),
            _ => {
                return Err("another process's lists are longer than MPI's counts reach".to_string())
            }
        };
        let flat: Vec<u64> = send.concat();
        let mut words = vec![0u64; receiving.iter().sum::<u64>() as usize];
        {
            let from = Partition::new(&flat[..], &send_counts[..], &send_displs[..]);
            let mut into = PartitionMut::new(&mut words[..], &counts[..], &displs[..]);
            self.comm.all_to_all_varcount_into(&from, &mut into);
        }
        Ok(split(words, &counts))
    }
}
