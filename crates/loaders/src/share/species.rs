//! Species names numbered across processes as one process numbers them: 1, 2, ... by first
//! appearance in the frame's glyph order (id order), so a name's number is its rank by the
//! smallest global index of a glyph bearing it. Each process gives its names with their
//! smallest index; every process then orders the union alike.

use std::collections::HashMap;

use super::collective::{pack, unpack_at, Collective};
use crate::Result;

/// The number of each of this process's `names`, given the smallest global index of a kept
/// glyph bearing each (`None`: only invalid lines bear it, and it is not numbered here).
pub(crate) fn number_names(
    names: &[&[u8]],
    first: &[Option<u64>],
    c: Collective,
) -> Result<Vec<Option<i64>>> {
    let mut mine = Vec::new();
    for (name, at) in names.iter().zip(first) {
        if let Some(at) = at {
            mine.push(*at);
            mine.extend(pack(name));
        }
    }
    let all = c.gather(&mine)?;
    let mut smallest: HashMap<Vec<u8>, u64> = HashMap::new();
    for list in &all {
        let mut k = 0;
        while k < list.len() {
            let at = list[k];
            let (name, used) = unpack_at(&list[k + 1..]);
            k += 1 + used;
            let entry = smallest.entry(name).or_insert(at);
            *entry = (*entry).min(at);
        }
    }
    let mut order: Vec<(u64, Vec<u8>)> = smallest.into_iter().map(|(n, at)| (at, n)).collect();
    order.sort_unstable();
    let number: HashMap<Vec<u8>, i64> = order
        .into_iter()
        .enumerate()
        .map(|(k, (_, name))| (name, k as i64 + 1))
        .collect();
    Ok(names
        .iter()
        .zip(first)
        .map(|(name, at)| at.and_then(|_| number.get(*name).copied()))
        .collect())
}
