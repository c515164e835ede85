//! The steps every share reader takes with the other processes, built on [`Exchange`]: an
//! agreement that fails every process when one fails (so no process waits for another that
//! has stopped), sums and offsets of counts, and the text of the first process that has one.

use std::path::Path;

use super::exchange::Exchange;
use crate::{Error, Result};

/// The processes reading `file`, and the exchanges between them.
#[derive(Clone, Copy)]
pub(crate) struct Collective<'a> {
    exchange: &'a dyn Exchange,
    file: &'a Path,
}

impl<'a> Collective<'a> {
    pub fn new(exchange: &'a dyn Exchange, file: &'a Path) -> Self {
        Self { exchange, file }
    }

    pub fn rank(&self) -> usize {
        self.exchange.rank()
    }

    pub fn size(&self) -> usize {
        self.exchange.size()
    }

    fn failed(&self, reason: String) -> Error {
        Error::invalid("exchange between processes", reason)
    }

    /// Every process's `mine`, in rank order.
    pub fn gather(&self, mine: &[u64]) -> Result<Vec<Vec<u64>>> {
        let all = self.exchange.all_gather(mine).map_err(|r| self.failed(r))?;
        if all.len() != self.size() {
            return Err(self.failed(format!(
                "{} lists gathered from {} processes",
                all.len(),
                self.size()
            )));
        }
        Ok(all)
    }

    /// Sends `send[r]` to rank `r`; what each rank sent here.
    pub fn all_to_all(&self, send: &[Vec<u64>]) -> Result<Vec<Vec<u64>>> {
        let all = self.exchange.all_to_all(send).map_err(|r| self.failed(r))?;
        if all.len() != self.size() {
            return Err(self.failed(format!(
                "{} lists received from {} processes",
                all.len(),
                self.size()
            )));
        }
        Ok(all)
    }

    /// `local` where every process succeeded, with every process's `numbers` of its value;
    /// else this process's own error, or [`Error::OtherRank`] naming the lowest failing rank.
    /// One exchange: the failure travels with the numbers.
    pub fn agree<T>(
        &self,
        local: Result<T>,
        numbers: impl FnOnce(&T) -> Vec<u64>,
    ) -> Result<(T, Vec<Vec<u64>>)> {
        let mine = match &local {
            Ok(value) => std::iter::once(0).chain(numbers(value)).collect(),
            Err(_) => vec![1],
        };
        let all = self.gather(&mine)?;
        let value = local?;
        if let Some(rank) = all.iter().position(|l| l.first() != Some(&0)) {
            return Err(Error::OtherRank {
                rank,
                file: self.file.to_path_buf(),
            });
        }
        Ok((value, all.into_iter().map(|l| l[1..].to_vec()).collect()))
    }

    /// The text of the lowest rank that has one (the first skipped record's error in file
    /// order, since ranks read the file in order).
    pub fn first_text(&self, mine: Option<&str>) -> Result<Option<String>> {
        let all = self.gather(&mine.map(|t| pack(t.as_bytes())).unwrap_or_default())?;
        Ok(all
            .iter()
            .find(|l| !l.is_empty())
            .map(|l| String::from_utf8_lossy(&unpack_at(l).0).into_owned()))
    }
}

/// The sum of column `k` over every process's numbers.
pub(crate) fn sum(all: &[Vec<u64>], k: usize) -> u64 {
    all.iter().map(|l| l[k]).sum()
}

/// The sum of column `k` over the ranks before `rank`: where `rank`'s items start in the
/// whole.
pub(crate) fn offset(all: &[Vec<u64>], k: usize, rank: usize) -> u64 {
    all[..rank].iter().map(|l| l[k]).sum()
}

/// `bytes` as words: their length, then the bytes eight to a word.
pub(crate) fn pack(bytes: &[u8]) -> Vec<u64> {
    std::iter::once(bytes.len() as u64)
        .chain(bytes.chunks(8).map(|c| {
            let mut word = [0u8; 8];
            word[..c.len()].copy_from_slice(c);
            u64::from_le_bytes(word)
        }))
        .collect()
}

/// The bytes [`pack`] put first in `words`, and the number of words they took.
pub(crate) fn unpack_at(words: &[u64]) -> (Vec<u8>, usize) {
    let len = words.first().map_or(0, |&n| n as usize);
    let used = 1 + len.div_ceil(8);
    let bytes: Vec<u8> = words
        .get(1..used.min(words.len()))
        .unwrap_or_default()
        .iter()
        .flat_map(|w| w.to_le_bytes())
        .take(len)
        .collect();
    (bytes, used)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_packs_and_unpacks() {
        for text in [
            "",
            "a",
            "12345678",
            "123456789",
            "duplicate atom id 7 (also on line 3)",
        ] {
            let mut words = pack(text.as_bytes());
            words.push(99);
            let (back, used) = unpack_at(&words);
            assert_eq!(back, text.as_bytes());
            assert_eq!(words[used], 99, "{text:?}");
        }
    }
}
