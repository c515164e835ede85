//! Processes played by threads, for [`load_share`](ellipsoid_splat_loaders::load_share): an
//! [`Exchange`] whose members meet at a barrier to swap their lists.

use std::sync::{Barrier, Mutex};

use ellipsoid_splat_loaders::Exchange;

/// What the threads of one run share.
struct Shared {
    barrier: Barrier,
    /// Each member's latest list for `all_gather`, and lists for `all_to_all`.
    gathered: Mutex<Vec<Vec<u64>>>,
    sent: Mutex<Vec<Vec<Vec<u64>>>>,
}

/// One thread's place among the others.
pub struct Member<'a> {
    rank: usize,
    shared: &'a Shared,
}

impl Exchange for Member<'_> {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.shared.gathered.lock().unwrap().len()
    }

    fn all_gather(&self, mine: &[u64]) -> Result<Vec<Vec<u64>>, String> {
        self.shared.gathered.lock().unwrap()[self.rank] = mine.to_vec();
        self.shared.barrier.wait();
        let all = self.shared.gathered.lock().unwrap().clone();
        // Nobody writes the next round's lists before everyone has read this one's.
        self.shared.barrier.wait();
        Ok(all)
    }

    fn all_to_all(&self, send: &[Vec<u64>]) -> Result<Vec<Vec<u64>>, String> {
        self.shared.sent.lock().unwrap()[self.rank] = send.to_vec();
        self.shared.barrier.wait();
        let mine = self
            .shared
            .sent
            .lock()
            .unwrap()
            .iter()
            .map(|lists| lists[self.rank].clone())
            .collect();
        self.shared.barrier.wait();
        Ok(mine)
    }
}

/// `work` run by `size` threads at once, each with its [`Member`]; their results in rank
/// order.
pub fn run_as<R: Send>(size: usize, work: impl Fn(&dyn Exchange) -> R + Sync) -> Vec<R> {
    let shared = Shared {
        barrier: Barrier::new(size),
        gathered: Mutex::new(vec![Vec::new(); size]),
        sent: Mutex::new(vec![Vec::new(); size]),
    };
    std::thread::scope(|scope| {
        let handles: Vec<_> = (0..size)
            .map(|rank| {
                let member = Member {
                    rank,
                    shared: &shared,
                };
                let work = &work;
                scope.spawn(move || work(&member))
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    })
}
