//! Scripted input (`view --script FILE`): events fed to the viewer at given frames, so tests
//! and measurements drive a real window without a person.
//!
//! One event a line, `FRAME COMMAND ARGS...`; `#` starts a comment. Frames count every turn
//! of the render loop from 0, drawn or skipped (a minimised window skips), and never go
//! backwards. Pixel positions are window pixels from the top left. Commands:
//!
//! | command | effect |
//! |---|---|
//! | `press BUTTON X Y`, `release BUTTON X Y` | mouse button (`left`, `middle`, `right`, `shift+left`) |
//! | `move X Y` | the cursor moves |
//! | `click X Y` | left press and release in place: a pick |
//! | `drag BUTTON X0 Y0 X1 Y1 FRAMES` | press, move in FRAMES equal steps (one a frame), release |
//! | `wheel X Y NOTCHES` | the wheel at (X, Y); positive notches zoom in |
//! | `key K` | a key press (`F`, `R`, `O`, `P`, `C`, `N`, `B`, `SPACE`, `H`, `Q`) |
//! | `resize W H` | asks the window system for a new inner size |
//! | `minimise`, `restore` | minimises (hides) the window, shows it again |
//! | `screenshot FILE` | the next drawn frame, as shown, to a PNG |
//! | `animate N` | for N frames, one glyph a frame is recoloured through a scene update |
//! | `memory` | prints `memory: frame F gpu-scene B gpu-total B rss B` |
//! | `camera` | prints the `render` flags of the current camera |

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// The most frames one scripted drag may take (each is an event in memory).
const MAX_DRAG_FRAMES: u64 = 1_000_000;

/// A mouse button as scripts name it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Button {
    /// Orbit, and pick on a click.
    Left,
    /// Pan.
    Middle,
    /// Unused by the viewer; accepted so scripts can check it does nothing.
    Right,
    /// Left with shift held: pan.
    ShiftLeft,
}

/// One input event of a script.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// A button goes down at a position.
    Press(Button, f64, f64),
    /// A button goes up at a position.
    Release(Button, f64, f64),
    /// The cursor moves.
    Move(f64, f64),
    /// The wheel turns by some notches at a position.
    Wheel(f64, f64, f64),
    /// A key is pressed (upper-case letter).
    Key(char),
    /// The window is asked for a new inner size.
    Resize(u32, u32),
    /// The window is minimised.
    Minimise,
    /// The window is shown again.
    Restore,
    /// The next drawn frame goes to this PNG.
    Screenshot(PathBuf),
    /// Recolour one glyph a frame for this many frames.
    Animate(u64),
    /// Print the memory in use.
    Memory,
    /// Print the camera as `render` flags.
    Camera,
}

/// The events of a script, in frame order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Script {
    events: Vec<(u64, Action)>,
    next: usize,
}

impl Script {
    /// Reads and parses a script file; errors name the file and line.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            Error::invalid("--script", format!("cannot read '{}': {e}", path.display()))
        })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Parses script text; `name` is the file name errors mention.
    pub fn parse(text: &str, name: &str) -> Result<Self> {
        let mut events = Vec::new();
        let mut last_frame = 0;
        for (k, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            let fail = |why: String| Error::invalid("--script", format!("{name}:{}: {why}", k + 1));
            let words: Vec<&str> = line.split_whitespace().collect();
            let frame: u64 = words[0].parse().map_err(|_| {
                fail(format!(
                    "a line starts with its frame number, got '{}'",
                    words[0]
                ))
            })?;
            if frame < last_frame {
                return Err(fail(format!(
                    "frame {frame} comes after frame {last_frame}; frames never go backwards"
                )));
            }
            last_frame = frame;
            let Some(&command) = words.get(1) else {
                return Err(fail("a frame number needs a command after it".into()));
            };
            let args = &words[2..];
            let want = |n: usize, form: &str| {
                if args.len() == n {
                    Ok(())
                } else {
                    Err(fail(format!(
                        "'{command}' takes {n} argument(s): {command} {form}; got {}",
                        args.len()
                    )))
                }
            };
            let number = |i: usize| -> Result<f64> {
                let text = args[i];
                text.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| fail(format!("'{text}' is not a finite number")))
            };
            let count = |i: usize| -> Result<u64> {
                args[i]
                    .parse::<u64>()
                    .map_err(|_| fail(format!("'{}' is not a whole number", args[i])))
            };
            let button = |text: &str| match text {
                "left" => Ok(Button::Left),
                "middle" => Ok(Button::Middle),
                "right" => Ok(Button::Right),
                "shift+left" => Ok(Button::ShiftLeft),
                _ => Err(fail(format!(
                    "unknown button '{text}' (left, middle, right, shift+left)"
                ))),
            };
            match command {
                "press" | "release" => {
                    want(3, "BUTTON X Y")?;
                    let (b, x, y) = (button(args[0])?, number(1)?, number(2)?);
                    let action = if command == "press" {
                        Action::Press(b, x, y)
                    } else {
                        Action::Release(b, x, y)
                    };
                    events.push((frame, action));
                }
                "move" => {
                    want(2, "X Y")?;
                    events.push((frame, Action::Move(number(0)?, number(1)?)));
                }
                "click" => {
                    want(2, "X Y")?;
                    let (x, y) = (number(0)?, number(1)?);
                    events.push((frame, Action::Move(x, y)));
                    events.push((frame, Action::Press(Button::Left, x, y)));
                    events.push((frame, Action::Release(Button::Left, x, y)));
                }
                "drag" => {
                    want(6, "BUTTON X0 Y0 X1 Y1 FRAMES")?;
                    let b = button(args[0])?;
                    let (x0, y0, x1, y1) = (number(1)?, number(2)?, number(3)?, number(4)?);
                    let steps = count(5)?;
                    if !(1..=MAX_DRAG_FRAMES).contains(&steps) {
                        return Err(fail(format!(
                            "a drag takes 1 to {MAX_DRAG_FRAMES} frames, not {steps}"
                        )));
                    }
                    if frame.checked_add(steps).is_none() {
                        return Err(fail(format!(
                            "a drag from frame {frame} ends past the last frame"
                        )));
                    }
                    events.push((frame, Action::Move(x0, y0)));
                    events.push((frame, Action::Press(b, x0, y0)));
                    for s in 1..=steps {
                        let t = s as f64 / steps as f64;
                        let at = (x0 + (x1 - x0) * t, y0 + (y1 - y0) * t);
                        events.push((frame + s - 1, Action::Move(at.0, at.1)));
                    }
                    events.push((frame + steps - 1, Action::Release(b, x1, y1)));
                }
                "wheel" => {
                    want(3, "X Y NOTCHES")?;
                    let action = Action::Wheel(number(0)?, number(1)?, number(2)?);
                    events.push((frame, action));
                }
                "key" => {
                    want(1, "K")?;
                    let key = args[0].to_ascii_uppercase();
                    let mut chars = key.chars();
                    match (chars.next(), chars.next()) {
                        _ if key == "SPACE" => events.push((frame, Action::Key(' '))),
                        (Some(c @ ('F' | 'R' | 'O' | 'P' | 'C' | 'N' | 'B' | 'H' | 'Q')), None) => {
                            events.push((frame, Action::Key(c)))
                        }
                        _ => {
                            return Err(fail(format!(
                                "unknown key '{}' (F, R, O, P, C, N, B, SPACE, H, Q)",
                                args[0]
                            )))
                        }
                    }
                }
                "resize" => {
                    want(2, "W H")?;
                    let (w, h) = (count(0)?, count(1)?);
                    let side = |v: u64| u32::try_from(v).ok().filter(|v| (1..=16384).contains(v));
                    let (Some(w), Some(h)) = (side(w), side(h)) else {
                        return Err(fail(format!("{w}x{h} is not a size in 1..=16384")));
                    };
                    events.push((frame, Action::Resize(w, h)));
                }
                "minimise" | "minimize" => {
                    want(0, "")?;
                    events.push((frame, Action::Minimise));
                }
                "restore" => {
                    want(0, "")?;
                    events.push((frame, Action::Restore));
                }
                "screenshot" => {
                    want(1, "FILE.png")?;
                    events.push((frame, Action::Screenshot(PathBuf::from(args[0]))));
                }
                "animate" => {
                    want(1, "FRAMES")?;
                    events.push((frame, Action::Animate(count(0)?)));
                }
                "memory" => {
                    want(0, "")?;
                    events.push((frame, Action::Memory));
                }
                "camera" => {
                    want(0, "")?;
                    events.push((frame, Action::Camera));
                }
                _ => {
                    return Err(fail(format!(
                        "unknown command '{command}' (press, release, move, click, drag, wheel, \
                         key, resize, minimise, restore, screenshot, animate, memory, camera)"
                    )))
                }
            }
        }
        // Drags spread over frames; keep the events in frame order (stable for equal frames).
        events.sort_by_key(|(frame, _)| *frame);
        Ok(Self { events, next: 0 })
    }

    /// The events due at `frame` (and any earlier ones not yet taken).
    pub fn due(&mut self, frame: u64) -> Vec<Action> {
        let start = self.next;
        while self.next < self.events.len() && self.events[self.next].0 <= frame {
            self.next += 1;
        }
        self.events[start..self.next]
            .iter()
            .map(|(_, a)| a.clone())
            .collect()
    }

    /// Frame of the last event (0 for an empty script).
    pub fn last_frame(&self) -> u64 {
        self.events.last().map_or(0, |(f, _)| *f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_events_in_frame_order() {
        let text = "# orbit\n2 drag left 10 10 40 10 3\n3 key p\n6 screenshot a.png # then\n";
        let mut script = Script::parse(text, "s.txt").unwrap();
        assert_eq!(script.last_frame(), 6);
        assert_eq!(
            script.due(2),
            vec![
                Action::Move(10.0, 10.0),
                Action::Press(Button::Left, 10.0, 10.0),
                Action::Move(20.0, 10.0)
            ]
        );
        assert_eq!(
            script.due(3),
            vec![Action::Move(30.0, 10.0), Action::Key('P')]
        );
        assert_eq!(
            script.due(4),
            vec![
                Action::Move(40.0, 10.0),
                Action::Release(Button::Left, 40.0, 10.0)
            ]
        );
        assert_eq!(script.due(9), vec![Action::Screenshot("a.png".into())]);
        assert!(script.due(10).is_empty());
    }

    #[test]
    fn bad_lines_name_the_file_line_and_reason() {
        let cases = [
            (
                "x click 1 2",
                "s:1: a line starts with its frame number, got 'x'",
            ),
            ("\n5 key x", "s:2: unknown key 'x'"),
            ("3 move 1 2\n1 move 1 2", "s:2: frame 1 comes after frame 3"),
            ("1 click 1", "s:1: 'click' takes 2 argument(s)"),
            ("1 wheel 1 2 nan", "s:1: 'nan' is not a finite number"),
            ("1 resize 0 10", "s:1: 0x10 is not a size"),
            ("1 jump", "s:1: unknown command 'jump'"),
            ("1 drag up 0 0 1 1 2", "s:1: unknown button 'up'"),
            ("7", "s:1: a frame number needs a command"),
        ];
        for (text, expected) in cases {
            let e = Script::parse(text, "s").unwrap_err().to_string();
            assert!(
                e.contains("--script") && e.contains(expected),
                "{text}: {e}"
            );
        }
    }
}
