//! Which frames of a trajectory `render --frames` draws: `all`, one frame `N`, or `A:B[:STEP]`.
//! Frames are numbered from 1 (the first frame of the file is frame 1), as the loaders'
//! errors number them, and a range includes both ends.

use std::fmt;

/// The frames `--frames` names, before the file says how many it has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameRange {
    /// Every frame of the file.
    All,
    /// Frames `first`, `first + step`, ... up to and including `last` (`None`: the file's last).
    Range {
        /// The first frame drawn, 1-based.
        first: usize,
        /// The last frame that may be drawn, 1-based; `None` for the file's last.
        last: Option<usize>,
        /// The distance between frames drawn, at least 1.
        step: usize,
    },
}

impl FrameRange {
    /// Reads `all`, `N`, `A:B`, `A:` (to the end) or `A:B:STEP` (`A::STEP` to the end).
    pub fn parse(text: &str) -> std::result::Result<Self, String> {
        let text = text.trim();
        if text == "all" {
            return Ok(FrameRange::All);
        }
        let number = |part: &str, what: &str| -> std::result::Result<usize, String> {
            match part.trim().parse::<usize>() {
                Ok(0) => Err(format!(
                    "{what} is 0, but frames are numbered from 1 (the file's first frame is 1)"
                )),
                Ok(n) => Ok(n),
                Err(_) => Err(format!(
                    "{what} needs a whole number from 1, got '{part}' (use all, N, A:B or A:B:STEP)"
                )),
            }
        };
        let parts: Vec<&str> = text.split(':').collect();
        let (first, last, step) = match parts.as_slice() {
            [n] => {
                let n = number(n, "the frame")?;
                (n, Some(n), 1)
            }
            [a, b] => (
                number(a, "the first frame")?,
                optional(b, |b| number(b, "the last frame"))?,
                1,
            ),
            [a, b, s] => (
                number(a, "the first frame")?,
                optional(b, |b| number(b, "the last frame"))?,
                match s.trim().parse::<usize>() {
                    Ok(0) => return Err("the step is 0; it must be 1 or more".to_string()),
                    _ => number(s, "the step")?,
                },
            ),
            _ => {
                return Err(format!(
                    "'{text}' has {} colons; use all, N, A:B or A:B:STEP",
                    parts.len() - 1
                ))
            }
        };
        if let Some(last) = last {
            if last < first {
                return Err(format!(
                    "the last frame {last} comes before the first {first}"
                ));
            }
        }
        Ok(FrameRange::Range { first, last, step })
    }

    /// The 0-based indices of the frames to draw from a file of `frames` frames; an error
    /// (saying how many frames the file has) when the range starts or ends past the file.
    pub fn indices(&self, frames: usize) -> std::result::Result<Vec<usize>, String> {
        let (first, last, step) = match *self {
            FrameRange::All => (1, None, 1),
            FrameRange::Range { first, last, step } => (first, last, step),
        };
        // A range made in code rather than parsed may hold what `parse` refuses.
        if first == 0 || step == 0 || last.is_some_and(|last| last < first) {
            return Err(format!(
                "{self} is not a range of frames (they count from 1, the step from 1)"
            ));
        }
        let last = last.unwrap_or(frames);
        if frames == 0 {
            return Err("the file holds no frames".to_string());
        }
        if first > frames || last > frames {
            return Err(format!(
                "{self} reaches past the file's {frames} frame{}",
                if frames == 1 { "" } else { "s" }
            ));
        }
        Ok((first - 1..last).step_by(step).collect())
    }
}

/// `parse(part)`, or `None` when `part` is empty.
fn optional(
    part: &str,
    parse: impl FnOnce(&str) -> std::result::Result<usize, String>,
) -> std::result::Result<Option<usize>, String> {
    if part.trim().is_empty() {
        Ok(None)
    } else {
        parse(part).map(Some)
    }
}

impl fmt::Display for FrameRange {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        match *self {
            FrameRange::All => f.write_str("all"),
            FrameRange::Range { first, last, step } => {
                let last = last.map(|l| l.to_string()).unwrap_or_default();
                if step == 1 && last == first.to_string() {
                    write!(f, "frame {first}")
                } else if step == 1 {
                    write!(f, "frames {first}:{last}")
                } else {
                    write!(f, "frames {first}:{last}:{step}")
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_one_based_and_inclusive() {
        let parse = |t: &str| FrameRange::parse(t).unwrap();
        assert_eq!(parse("all").indices(4).unwrap(), vec![0, 1, 2, 3]);
        assert_eq!(parse("3").indices(4).unwrap(), vec![2]);
        assert_eq!(parse("2:4").indices(4).unwrap(), vec![1, 2, 3]);
        assert_eq!(parse("1:10:3").indices(10).unwrap(), vec![0, 3, 6, 9]);
        assert_eq!(parse("2:").indices(3).unwrap(), vec![1, 2]);
        assert_eq!(parse("1::2").indices(5).unwrap(), vec![0, 2, 4]);
    }

    #[test]
    fn bad_ranges_say_why() {
        let error = |t: &str| FrameRange::parse(t).unwrap_err();
        assert!(error("0").contains("numbered from 1"), "{}", error("0"));
        assert!(error("x:3").contains("'x'"));
        assert!(error("5:2").contains("before the first"));
        assert!(error("1:2:0").contains("the step is 0; it must be 1"));
        let made = FrameRange::Range {
            first: 0,
            last: None,
            step: 0,
        };
        assert!(made.indices(3).unwrap_err().contains("not a range"));
        assert!(error("1:2:3:4").contains("3 colons"));
        let past = FrameRange::parse("2:9").unwrap().indices(5).unwrap_err();
        assert!(past.contains("5 frames"), "{past}");
        let one = FrameRange::parse("2").unwrap().indices(1).unwrap_err();
        assert!(one.contains("1 frame"), "{one}");
    }
}
