//! `--script PATH`: timed viewer actions, one per line, so a session is reproducible.
//!
//! ```text
//! # frame  action        arguments
//! 0        camera        0,1.7,8,0,-12      # X,Y,Z,YAW_DEG,PITCH_DEG
//! 0        time          2.5                # set the simulation time
//! 0        pause                            # freeze (or resume) the simulation time
//! 10       key           w down             # hold a key (names as in the help, H)
//! 40       key           w up
//! 41       press         m                  # down and up
//! 50       click         160,100            # left click at a pixel (drops a wind source)
//! 52       collider      sphere:0,0.3,2,0.3,1.5,0,0   # add a collider (--collider's shapes)
//! 54       move-collider 0 1,0.3,2.5        # put collider 0 there (at rest): a path, frame by frame
//! 60       resize        640x360
//! 70       minimise
//! 80       restore
//! 90       screenshot    shot.png
//! 92       ui-click      GPU culling        # the overlay's control of that label
//! 94       ui-drag       40 wind strength   # drag a slider 40 pixels right
//! 100      quit
//! ```
//!
//! Frames are counted from the first rendered frame; actions of a frame run before it renders.
//! With a script (or `--frames`), simulation time advances by a fixed 1/60 s per frame.

use crate::error::{quoted, Error, Result};
use crate::scene::Camera;

/// Largest script `--script` reads (a session of a million actions is about 20 MB: more than any
/// test or soak plays).
const MOST_BYTES: u64 = 32 << 20;

/// One scripted action.
#[derive(Clone, Debug, PartialEq)]
pub enum Action {
    /// Put the camera there.
    Camera(Camera),
    /// Set the simulation time.
    Time(f32),
    /// Toggle pause.
    Pause,
    /// Press (true) or release (false) a key by name.
    Key(String, bool),
    /// Press and release a key.
    Press(String),
    /// Left click at a pixel.
    Click(f64, f64),
    /// Add a collider (`--collider`'s shapes, moving or not).
    Collider(crate::wind::Collider),
    /// Put collider `index`'s centre at a world point, at rest.
    MoveCollider(usize, glam::Vec3),
    /// Ask the window for a new inner size.
    Resize(u32, u32),
    /// Minimise the window.
    Minimise,
    /// Restore it.
    Restore,
    /// Write the next frame to a PNG.
    Screenshot(String),
    /// Click the overlay's control of this label (pointer events through egui's input).
    UiClick(String),
    /// Drag the overlay's control of this label (a slider) by a number of pixels to the right.
    UiDrag(f32, String),
    /// Close the viewer.
    Quit,
}

/// `move-collider INDEX X,Y,Z`'s arguments.
fn move_collider(args: &[&str]) -> std::result::Result<Action, String> {
    const SHAPE: &str = "move-collider INDEX X,Y,Z";
    let [index, at] = args else { return Err(SHAPE.into()) };
    let index = index.parse().map_err(|_| SHAPE.to_string())?;
    let v = at.split(',').map(crate::app::values::finite_f32).collect::<std::result::Result<Vec<f32>, _>>()?;
    match v.as_slice() {
        [x, y, z] => Ok(Action::MoveCollider(index, glam::Vec3::new(*x, *y, *z))),
        _ => Err(SHAPE.into()),
    }
}

/// Actions sorted by frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Script {
    /// (frame, action), in order.
    pub actions: Vec<(u64, Action)>,
}

impl Script {
    /// Read and parse a script file.
    pub fn load(path: &std::path::Path) -> Result<Self> {
        let text = crate::app::input::read_text(path, "--script", MOST_BYTES, 4)?;
        Self::parse(&text)
            .map_err(|e| Error::bad_input(format!("--script {}: {e}", quoted(&path.display().to_string()))))
    }

    /// Parse the text of a script.
    pub fn parse(text: &str) -> std::result::Result<Self, String> {
        let mut actions = Vec::new();
        for (n, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            // The line as written, bounded (`error::quoted`): a megabyte line is not echoed whole.
            // What went wrong may quote a word of the line, bounded where it is quoted.
            let fail = |what: &str| format!("line {}: {what}: '{}'", n + 1, quoted(raw));
            let mut words = line.split_whitespace();
            let frame: u64 =
                words.next().and_then(|w| w.parse().ok()).ok_or_else(|| fail("expected a frame number"))?;
            let verb = words.next().ok_or_else(|| fail("expected an action"))?;
            let args: Vec<&str> = words.collect();
            let one = |what: &str| -> std::result::Result<&str, String> {
                match args.as_slice() {
                    [a] => Ok(*a),
                    _ => Err(fail(what)),
                }
            };
            let none = |action: Action| match args.is_empty() {
                true => Ok(action),
                false => Err(fail(&format!("{} takes no arguments", quoted(verb)))),
            };
            let key = |name: &str| match super::keys::KEY_NAMES.contains(&name.to_lowercase().as_str()) {
                true => Ok(name.to_lowercase()),
                false => Err(fail(&format!("unknown key '{}' (the help, H, names them)", quoted(name)))),
            };
            let action = match verb {
                "camera" => {
                    Action::Camera(crate::app::values::camera(one("camera X,Y,Z,YAW,PITCH")?).map_err(|e| fail(&e))?)
                }
                "time" => Action::Time(crate::app::values::time(one("time SECONDS")?).map_err(|e| fail(&e))?),
                "pause" => none(Action::Pause)?,
                "key" => match args.as_slice() {
                    [name, "down"] => Action::Key(key(name)?, true),
                    [name, "up"] => Action::Key(key(name)?, false),
                    _ => return Err(fail("key NAME down|up")),
                },
                "press" => Action::Press(key(one("press NAME")?)?),
                "click" => {
                    let xy = one("click X,Y")?;
                    let (x, y) = xy.split_once(',').ok_or_else(|| fail("click X,Y"))?;
                    let parse = |v: &str| crate::app::values::finite_f32(v).map(f64::from).map_err(|e| fail(&e));
                    Action::Click(parse(x)?, parse(y)?)
                }
                "collider" => Action::Collider(
                    crate::app::values::collider(one("collider sphere:X,Y,Z,R[,VX,VY,VZ] or ellipsoid:…")?)
                        .map_err(|e| fail(&e))?,
                ),
                "move-collider" => move_collider(&args).map_err(|e| fail(&e))?,
                "resize" => {
                    let (w, h) = crate::app::values::size(one("resize WxH")?).map_err(|e| fail(&e))?;
                    Action::Resize(w, h)
                }
                "minimise" | "minimize" => none(Action::Minimise)?,
                "restore" => none(Action::Restore)?,
                "screenshot" => Action::Screenshot(one("screenshot PATH")?.to_string()),
                "ui-click" if !args.is_empty() => Action::UiClick(args.join(" ")),
                "ui-drag" => match args.split_first() {
                    Some((dx, label)) if !label.is_empty() => {
                        let dx = crate::app::values::finite_f32(dx).map_err(|e| fail(&e))?;
                        Action::UiDrag(dx, label.join(" "))
                    }
                    _ => return Err(fail("ui-drag DX_PIXELS LABEL")),
                },
                "ui-click" => return Err(fail("ui-click LABEL")),
                "quit" => none(Action::Quit)?,
                other => return Err(fail(&format!("unknown action '{}'", quoted(other)))),
            };
            actions.push((frame, action));
        }
        actions.sort_by_key(|(frame, _)| *frame);
        Ok(Self { actions })
    }

    /// Remove and return the actions due at `frame` or before.
    pub fn due(&mut self, frame: u64) -> Vec<Action> {
        let split = self.actions.partition_point(|(f, _)| *f <= frame);
        self.actions.drain(..split).map(|(_, a)| a).collect()
    }

    /// Whether any action is left.
    pub fn is_empty(&self) -> bool {
        self.actions.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_action_in_frame_order() {
        let s = Script::parse(
            "# a comment\n10 key w down\n0 camera 0,1.7,8,0,-12\n5 resize 1x1\n7 click 10,20\n12 press F12 # inline\n99 quit\n",
        )
        .expect("valid");
        assert_eq!(s.actions.len(), 6);
        assert_eq!(s.actions[0].0, 0);
        assert_eq!(s.actions[2].1, Action::Click(10.0, 20.0));
        assert_eq!(s.actions[3].1, Action::Key("w".into(), true));
        // Key names are case-insensitive.
        assert_eq!(s.actions[4].1, Action::Press("f12".into()));
        let mut s = s;
        assert_eq!(s.due(6).len(), 2);
        assert_eq!(s.due(6).len(), 0);
    }

    #[test]
    fn reports_bad_lines_with_their_number() {
        let e = Script::parse("0 camera 0,1\n").unwrap_err();
        assert!(e.starts_with("line 1"), "{e}");
        assert!(Script::parse("x quit\n").is_err());
        assert!(Script::parse("3 dance\n").unwrap_err().contains("unknown action"));
        assert!(Script::parse("3 resize 0x0\n").is_err());
        // Colliders (issue 34): --collider's shapes, and a move to a finite point.
        let s = Script::parse("1 collider sphere:0,0.3,2,0.3,1.5,0,0\n2 move-collider 0 1,0.3,2.5\n").expect("valid");
        assert!(matches!(s.actions[0].1, Action::Collider(c) if c.velocity.x == 1.5));
        assert_eq!(s.actions[1].1, Action::MoveCollider(0, glam::Vec3::new(1.0, 0.3, 2.5)));
        for bad in [
            "1 collider sphere:0,0,0,0\n",
            "1 move-collider 0 1,NaN,2\n",
            "1 move-collider x 1,2,3\n",
            "1 move-collider 0 1,2\n",
        ] {
            assert!(Script::parse(bad).is_err(), "{bad}");
        }
        // Issue 11: extra arguments, unknown keys, and an overlong line echoed whole.
        assert!(Script::parse("3 quit now please\n").unwrap_err().contains("takes no arguments"));
        assert!(Script::parse("3 pause 2\n").is_err());
        assert!(Script::parse("3 press warp\n").unwrap_err().contains("unknown key 'warp'"));
        assert!(Script::parse("3 key nope down\n").is_err());
        for long in [
            format!("3 dance {}\n", "x".repeat(10_000_000)),
            format!("3 {}\n", "q".repeat(10_000_000)),
            format!("3 press {}\n", "a".repeat(10_000_000)),
            format!("3 camera {}\n", "1".repeat(10_000_000)),
            format!("3 resize {}x9\n", "9".repeat(10_000_000)),
        ] {
            let e = Script::parse(&long).unwrap_err();
            assert!(e.len() < 300, "{} bytes of error", e.len());
        }
    }
}
