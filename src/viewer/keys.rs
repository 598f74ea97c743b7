//! The viewer's keys: named keys (from the window or a script) change the camera, the wind and
//! the render settings. What a click, the arrow keys and F7 place in the wind is `emitters`.

use std::path::PathBuf;

use winit::keyboard::KeyCode;

use super::Viewer;
use crate::error::Result;
use crate::keyframes::Smoothing;
use crate::render::animation::sine::SinePhase;
use crate::render::animation::{Eval, Mode};

/// The keys whose control changes pipelines or the scene (`rebuild_for`).
const REBUILT_BY: [&str; 20] =
    ["m", "n", "b", "v", "x", "t", "o", "y", "f", "f2", "f3", "f4", "f5", "f6", "f8", "r", "plus", "minus", "[", "]"];

/// F4's slope limit when `--slope-limit` was not given, in degrees.
pub(super) const DEFAULT_SLOPE_LIMIT_DEG: f32 = 30.0;
/// F5's clump size when `--clumps` was not given, in metres.
pub(super) const DEFAULT_CLUMP_SIZE_M: f32 = 1.5;
/// F6's flowers per m² when `--flowers` was not given.
pub(super) const DEFAULT_FLOWERS_PER_M2: f32 = 20.0;

/// The controls, printed at start and by H.
pub(super) const HELP: &str = "\
meadow viewer controls
  W A S D / Q E   move / down, up       right mouse drag  look
  Shift           faster                 wheel             speed
  G               walk on the ground     H                 this help
  M               mode static/texture/uniform/sine object/vertex/verlet/inertial/virtual/floor
  N               smoothing nearest/linear/slerp
  B               evaluation per vertex / per blade (compute)
  + / -           segments               [ / ]             blades / 2, x 2
  J / L           wind direction -/+15   I / K             wind strength +/-
  U               gusts on/off           C                 calm areas on/off
  F2              wind field analytic / Perlin (Belyaev) / fluid (Zhang Xia)
  F3              wind view: arrows of the wind the grass feels, 0.5 m up
  F4              slope limit on/off (--slope-limit, or 30 degrees): steep ground bare
  F5              blades in clumps on/off (--clumps, or 1.5 m)
  F6              flowers on/off (--flowers, or 20 per square metre)
  left click      drop a wind source (drag to move)   Delete  remove the last source
  Shift + click   drop a collider sphere on the ground
  arrow keys      drive the collider sphere through the grass
  F7              trample as I walk: a sphere on the ground under the eye pushes the grass aside
  F8              pressed view: the trails and cuts of the pressed map, green to magenta
  V               force debug view       F                 wireframe
  X               cluster bounds view    T                 LOD / tile / Fresnel / cover view
  O               GPU culling / brute force             Y  LOD on/off
  Z               freeze the culling camera (fly out and look at what it keeps)
  R               MSAA: off, 4x alpha to coverage, 4x alpha test (the device's counts)
  P               pause time             F12               screenshot
  F1              the overlay: every control, live GPU timing, trace capture
  Esc             quit";

impl Viewer {
    /// A named key went down or up (from the window or a script).
    pub(super) fn key(&mut self, name: &str, pressed: bool) -> Result<()> {
        if self.control.key(name, pressed) || !pressed {
            return Ok(());
        }
        let renderer = self.renderer.as_mut().expect("renderer built");
        let wind = renderer.wind_mut();
        let mut rebuild = false;
        match name {
            "h" => println!("{HELP}"),
            "escape" => self.quit = true,
            "p" => self.paused = !self.paused,
            "g" => self.control.walk = !self.control.walk,
            "f12" => {
                self.screenshots_taken += 1;
                self.screenshot = Some(PathBuf::from(format!("meadow-screenshot-{}.png", self.screenshots_taken)));
            }
            "j" | "l" => {
                let global = wind.global.get_or_insert(crate::wind::GlobalWind {
                    direction_deg: 0.0,
                    strength: 0.3,
                    gusts: true,
                });
                global.direction_deg += if name == "j" { -15.0 } else { 15.0 };
                println!("wind direction {:.0} deg", global.direction_deg);
            }
            "i" | "k" => {
                let global = wind.global.get_or_insert(crate::wind::GlobalWind {
                    direction_deg: 0.0,
                    strength: 0.0,
                    gusts: true,
                });
                global.strength = (global.strength + if name == "i" { 0.05 } else { -0.05 }).max(0.0);
                println!("wind strength {:.2}", global.strength);
            }
            "u" => {
                if let Some(global) = wind.global.as_mut() {
                    global.gusts = !global.gusts;
                    println!("gusts {}", if global.gusts { "on" } else { "off" });
                }
            }
            "c" => match self.calm_off.take() {
                Some(calm) => wind.calm = calm,
                None => self.calm_off = Some(std::mem::take(&mut wind.calm)),
            },
            "delete" => {
                wind.sources.pop();
            }
            "up" | "down" | "left" | "right" => self.drive_collider(name),
            "f7" => {
                self.trample = !self.trample;
                println!("trample as I walk {}", if self.trample { "on" } else { "off" });
            }
            "z" => self.toggle_cull_freeze(),
            "f1" => self.toggle_overlay(),
            name if REBUILT_BY.contains(&name) => rebuild = true,
            _ => {}
        }
        if rebuild {
            self.rebuild_for(name)?;
        }
        Ok(())
    }

    /// Freeze the culling camera where the view is, or thaw it: fly out and look at what the
    /// frozen frustum and LOD keep.
    fn toggle_cull_freeze(&mut self) {
        let renderer = self.renderer.as_mut().expect("renderer built");
        let frozen = renderer.cull_camera().is_none().then_some(self.control.camera);
        renderer.set_cull_camera(frozen);
        println!("culling camera {}", if frozen.is_some() { "frozen" } else { "follows the view" });
    }

    /// Apply a control that changes pipelines or the scene, and rebuild the renderer. A change the
    /// device cannot take is reported and undone; the viewer carries on with what it had.
    pub(super) fn rebuild_for(&mut self, name: &str) -> Result<()> {
        if matches!(name, "[" | "]") && self.scene.field.is_some() {
            println!("cannot apply '{name}': a --field has a density, not a blade count");
            return Ok(());
        }
        let mut animation = self.renderer.as_ref().expect("renderer built").animation().clone();
        let mut settings = self.settings;
        // The blades asked for (a stored field under cover rules keeps fewer).
        let old_blades = self.options.scene.blades;
        let mut blades = old_blades;
        match name {
            // Static, texture, uniform, Pelzer's sine per object, vertex and cluster, Verlet, inertial,
            // virtually-inertial, then the floor
            // reference (static blades, pre-expanded).
            "m" => match (animation.mode, settings.floor) {
                (_, true) => settings.floor = false,
                (Mode::Static, false) => animation.mode = Mode::Texture,
                (Mode::Texture, false) => animation.mode = Mode::Uniform,
                (Mode::Uniform, false) => animation.mode = Mode::Sine(SinePhase::Object),
                (Mode::Sine(SinePhase::Object), false) => animation.mode = Mode::Sine(SinePhase::Vertex),
                (Mode::Sine(SinePhase::Vertex), false) => animation.mode = Mode::Sine(SinePhase::Cluster),
                (Mode::Sine(SinePhase::Cluster), false) => animation.mode = Mode::Verlet,
                (Mode::Verlet, false) => animation.mode = Mode::Inertial,
                (Mode::Inertial, false) => animation.mode = Mode::VirtualInertial,
                // The floor draws no flowers (refused with them): static blades instead.
                (Mode::VirtualInertial, false) => {
                    (animation.mode, settings.floor) = (Mode::Static, self.options.scene.flowers.is_none())
                }
            },
            "n" => {
                animation.smoothing = match animation.smoothing {
                    Smoothing::Nearest => Smoothing::Linear,
                    Smoothing::Linear => Smoothing::Slerp,
                    Smoothing::Slerp => Smoothing::Nearest,
                }
            }
            "b" => animation.eval = if animation.eval == Eval::Vertex { Eval::Blade } else { Eval::Vertex },
            "v" => settings.debug_force = !settings.debug_force,
            "x" => settings.debug_bounds = !settings.debug_bounds,
            "f3" => settings.debug_wind = !settings.debug_wind,
            // Off, the pressed map, the interaction patches.
            "f8" => {
                (settings.debug_pressed, settings.debug_patches) =
                    match (settings.debug_pressed, settings.debug_patches) {
                        (false, false) => (true, false),
                        (true, _) => (false, true),
                        (false, true) => (false, false),
                    }
            }
            "t" => cycle_cull_views(&mut settings),
            "o" | "y" => toggle_culling(&mut settings.culling, name),
            "f" => settings.wireframe = !settings.wireframe,
            "f2" => {
                use crate::render::wind::FieldKind;
                animation.wind_field = match animation.wind_field {
                    FieldKind::Analytic => FieldKind::Perlin,
                    FieldKind::Perlin => FieldKind::Fluid,
                    FieldKind::Fluid => FieldKind::Analytic,
                }
            }
            "r" => settings.msaa = next_msaa(settings.msaa, &crate::render::msaa::supported_counts(&self.device)),
            "plus" | "minus" => step_segments(&mut settings, name == "plus"),
            "[" => blades = (blades / 2).max(1),
            "]" => blades = blades.saturating_mul(2),
            _ => {}
        }
        let what = format!("'{name}'");
        if matches!(name, "f4" | "f5" | "f6") {
            return self.toggle_landscape(name, settings, animation);
        }
        if blades == old_blades {
            self.rebuild_passes(&what, settings, animation)?;
            return Ok(());
        }
        let scene = self.scene_with(blades)?;
        if self.replace_renderer(&what, Some(scene), settings, animation)? {
            self.options.scene.blades = blades;
        }
        Ok(())
    }
}

/// + / −: one segment more or fewer, the LOD buckets halving from the new count.
fn step_segments(s: &mut crate::render::RenderSettings, more: bool) {
    s.segments = if more { (s.segments + 1).min(16) } else { s.segments.saturating_sub(1).max(1) };
    s.culling.lod_segments = crate::render::culling::LodSegments::halving(s.segments);
}

/// R: no multisampling, then each supported count with alpha to coverage, then the largest with
/// the alpha test, then none again.
fn next_msaa(m: crate::render::msaa::Msaa, supported: &[u32]) -> crate::render::msaa::Msaa {
    use crate::render::msaa::Msaa;
    let largest = supported.iter().copied().max().unwrap_or(1);
    let next_count = supported.iter().copied().find(|&n| n > m.samples);
    match (m.alpha_to_coverage, next_count) {
        (true, Some(samples)) => Msaa { samples, alpha_to_coverage: true },
        (true, None) if largest > 1 => Msaa { samples: largest, alpha_to_coverage: false },
        _ => Msaa::default(),
    }
}

/// T: the LOD bucket view, then the tile view, the Fresnel term's, the cover's, then none.
fn cycle_cull_views(s: &mut crate::render::RenderSettings) {
    let views = (s.debug_lod, s.debug_tiles, s.debug_fresnel, s.debug_cover, s.debug_far);
    (s.debug_lod, s.debug_tiles, s.debug_fresnel, s.debug_cover, s.debug_far) = match views {
        (true, ..) => (false, true, false, false, false),
        (false, true, ..) => (false, false, true, false, false),
        (false, false, true, ..) => (false, false, false, true, false),
        (false, false, false, true, _) => (false, false, false, false, true),
        (false, false, false, false, true) => (false, false, false, false, false),
        (false, false, false, false, false) => (true, false, false, false, false),
    };
}

/// O: GPU culling or brute force; Y: the LOD (density, segments, outline) on or off.
fn toggle_culling(culling: &mut crate::render::culling::Culling, key: &str) {
    if key == "o" {
        culling.enabled = !culling.enabled;
    } else {
        let on = !(culling.density || culling.segment_lod || culling.solid_outline);
        (culling.density, culling.segment_lod, culling.solid_outline) = (on, on, on);
    }
}

/// Every key name the viewer acts on (what `key_name` returns), for scripts to check against.
pub(super) const KEY_NAMES: [&str; 46] = [
    "[", "]", "a", "b", "c", "d", "delete", "down", "e", "escape", "f", "f1", "f12", "f2", "f3", "f4", "f5", "f6",
    "f7", "f8", "g", "h", "i", "j", "k", "l", "left", "m", "minus", "n", "o", "p", "plus", "q", "r", "right", "s",
    "shift", "t", "u", "up", "v", "w", "x", "y", "z",
];

/// Name of a key as the help and scripts spell it.
pub(super) fn key_name(code: KeyCode) -> Option<&'static str> {
    Some(match code {
        KeyCode::KeyW => "w",
        KeyCode::KeyA => "a",
        KeyCode::KeyS => "s",
        KeyCode::KeyD => "d",
        KeyCode::KeyQ => "q",
        KeyCode::KeyE => "e",
        KeyCode::ShiftLeft | KeyCode::ShiftRight => "shift",
        KeyCode::KeyG => "g",
        KeyCode::KeyH => "h",
        KeyCode::KeyM => "m",
        KeyCode::KeyN => "n",
        KeyCode::KeyB => "b",
        KeyCode::Equal | KeyCode::NumpadAdd => "plus",
        KeyCode::Minus | KeyCode::NumpadSubtract => "minus",
        KeyCode::BracketLeft => "[",
        KeyCode::BracketRight => "]",
        KeyCode::KeyJ => "j",
        KeyCode::KeyL => "l",
        KeyCode::KeyI => "i",
        KeyCode::KeyK => "k",
        KeyCode::KeyU => "u",
        KeyCode::KeyC => "c",
        KeyCode::KeyV => "v",
        KeyCode::KeyX => "x",
        KeyCode::KeyT => "t",
        KeyCode::KeyO => "o",
        KeyCode::KeyY => "y",
        KeyCode::KeyZ => "z",
        KeyCode::KeyF => "f",
        KeyCode::KeyP => "p",
        KeyCode::KeyR => "r",
        KeyCode::F12 => "f12",
        KeyCode::F1 => "f1",
        KeyCode::F2 => "f2",
        KeyCode::F3 => "f3",
        KeyCode::F4 => "f4",
        KeyCode::F5 => "f5",
        KeyCode::F6 => "f6",
        KeyCode::F7 => "f7",
        KeyCode::F8 => "f8",
        KeyCode::Delete | KeyCode::Backspace => "delete",
        KeyCode::ArrowUp => "up",
        KeyCode::ArrowDown => "down",
        KeyCode::ArrowLeft => "left",
        KeyCode::ArrowRight => "right",
        KeyCode::Escape => "escape",
        _ => return None,
    })
}
