//! Global indices from atom ids across processes: one process loading a frame sorts its atoms
//! by id, so an atom's index is the number of atoms, over every process, with a smaller id.
//! Each id goes to the process that owns its part of the id range (an even cut of
//! [least id, greatest id]); the owner sorts what it gets, finds ids given twice, numbers its
//! ids from the counts of the owners before it, and sends each index back to where its id came
//! from. Two exchanges of eight bytes an atom, exact for any ids.

use super::collective::{offset, Collective};
use crate::Result;

/// What numbering the ids found.
pub(crate) enum Numbered {
    /// The global index of each id given, in their order.
    Indices(Vec<u64>),
    /// The smallest id that two atoms (on any processes) have.
    Duplicate(i64),
}

/// The global indices of `ids` (this process's, ascending; every process calls this with its
/// own, at least one process having some).
pub(crate) fn number_ids(ids: &[i64], c: Collective) -> Result<Numbered> {
    let (least, most) = (ids.first().copied(), ids.last().copied());
    let mine = [
        ids.len() as u64,
        least.unwrap_or(i64::MAX) as u64,
        most.unwrap_or(i64::MIN) as u64,
    ];
    let all = c.gather(&mine)?;
    let holding = || all.iter().filter(|l| l[0] > 0);
    let least = holding().map(|l| l[1] as i64).min().unwrap_or(0);
    let most = holding().map(|l| l[2] as i64).max().unwrap_or(0);
    // i128: the span of two i64 ids cannot overflow.
    let span = (i128::from(most) - i128::from(least) + 1).max(1) as u128;
    let size = c.size();
    let owner =
        |id: i64| ((i128::from(id) - i128::from(least)) as u128 * size as u128 / span) as usize;
    let mut send = vec![Vec::new(); size];
    for &id in ids {
        // Offsets from the least id fit in u64.
        send[owner(id)].push((i128::from(id) - i128::from(least)) as u64);
    }
    let received = c.all_to_all(&send)?;
    // Every id this process owns, with where it came from.
    let mut owned: Vec<(u64, usize, usize)> = received
        .iter()
        .enumerate()
        .flat_map(|(from, list)| list.iter().enumerate().map(move |(k, &v)| (v, from, k)))
        .collect();
    owned.sort_unstable();
    let duplicate = owned
        .windows(2)
        .find(|w| w[0].0 == w[1].0)
        .map_or(u64::MAX, |w| w[0].0);
    let counts = c.gather(&[owned.len() as u64, duplicate])?;
    if let Some(smallest) = counts.iter().map(|l| l[1]).filter(|&d| d != u64::MAX).min() {
        return Ok(Numbered::Duplicate(
            (i128::from(least) + i128::from(smallest)) as i64,
        ));
    }
    let first = offset(&counts, 0, c.rank());
    let mut reply: Vec<Vec<u64>> = received.iter().map(|l| vec![0; l.len()]).collect();
    for (place, &(_, from, k)) in owned.iter().enumerate() {
        reply[from][k] = first + place as u64;
    }
    // Sent in owner order, ascending: the replies in owner order are the ids' order.
    let back = c.all_to_all(&reply)?;
    Ok(Numbered::Indices(back.into_iter().flatten().collect()))
}
