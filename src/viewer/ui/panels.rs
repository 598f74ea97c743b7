//! The overlay's control panels: everything the keys and flags reach (scene, animation, view).
//! A widget does not change the viewer itself: it returns [`UiAction`]s, which the viewer applies
//! through the same paths as its keys (a rebuild that fails is reported and undone the same way).

use egui::Ui;

use crate::keyframes::Smoothing;
use crate::render::animation::{AnimationSettings, Eval, Mode};
use crate::render::RenderSettings;

/// What a widget asks the viewer to do.
#[derive(Clone, Debug, PartialEq)]
pub enum UiAction {
    /// Press a key `times` times (a control that cycles: M, N, T, R, ...).
    Press(&'static str, usize),
    /// Set the global wind's direction (degrees) and strength.
    Wind { direction_deg: f32, strength: f32 },
    /// Gust fronts on or off.
    Gusts(bool),
    /// Set point source `index`'s power.
    SourcePower(usize, f32),
    /// Remove point source `index`.
    RemoveSource(usize),
    /// Remove collider `index`.
    RemoveCollider(usize),
    /// Write the trace of the next `frames` frames into `--capture-dir`.
    Capture(u32),
}

/// What the panels produce in a frame: the actions asked for, and where each labelled control
/// was drawn (for scripts, which click controls by label through egui's pointer input).
#[derive(Default)]
pub struct PanelOutput {
    /// Actions, in the order the widgets were used.
    pub actions: Vec<UiAction>,
    /// (label, rectangle in points) of every labelled control drawn.
    pub widgets: Vec<(String, egui::Rect)>,
}

impl PanelOutput {
    pub(super) fn act(&mut self, action: UiAction) {
        self.actions.push(action);
    }

    /// Remember where control `label` was drawn; returns the response.
    pub(super) fn widget(&mut self, label: &str, response: egui::Response) -> egui::Response {
        self.widgets.push((label.to_string(), response.rect));
        response
    }
}

/// What the panels show: the viewer's state this frame.
pub struct UiView<'a> {
    /// The renderer's settings.
    pub settings: &'a RenderSettings,
    /// The animation, the wind included.
    pub animation: &'a AnimationSettings,
    /// Blades stored, or the field's size and density.
    pub scene: String,
    /// The culling camera is frozen (Z).
    pub frozen: bool,
    /// Time is paused (P).
    pub paused: bool,
    /// The camera walks on the ground (G).
    pub walk: bool,
    /// Calm areas are on (C).
    pub calm: bool,
    /// `--budget-ms` and the LOD scale it sets.
    pub budget: Option<(f32, f32)>,
    /// Present mode and frames in flight (set at start).
    pub presentation: String,
    /// Frames `--capture-dir` can take, or why there is no capture.
    pub capture: Result<(), &'static str>,
}

/// A choice among values a key cycles through: `presses` of `key` from `current` to each.
fn cycle(ui: &mut Ui, out: &mut PanelOutput, key: &'static str, labels: &[&str], current: usize) {
    ui.horizontal(|ui| {
        for (i, label) in labels.iter().enumerate() {
            if out.widget(label, ui.selectable_label(i == current, *label)).clicked() && i != current {
                out.act(UiAction::Press(key, (i + labels.len() - current) % labels.len()));
            }
        }
    });
}

/// A toggle shown as a checkbox, applied by its key.
fn toggle(ui: &mut Ui, out: &mut PanelOutput, key: &'static str, on: bool, label: &str) {
    let mut value = on;
    if out.widget(label, ui.checkbox(&mut value, label)).changed() {
        out.act(UiAction::Press(key, 1));
    }
}

/// Scene: blades or field, segments and LOD, culling, the frozen culling camera, the budget.
pub fn scene(ui: &mut Ui, view: &UiView, out: &mut PanelOutput) {
    let s = view.settings;
    ui.label(&view.scene);
    ui.horizontal(|ui| {
        if out.widget("blades / 2", ui.button("blades / 2")).clicked() {
            out.act(UiAction::Press("[", 1));
        }
        if out.widget("blades x 2", ui.button("blades x 2")).clicked() {
            out.act(UiAction::Press("]", 1));
        }
    });
    ui.horizontal(|ui| {
        ui.label(format!("{} segments", s.segments));
        if out.widget("segments -", ui.button("-")).clicked() {
            out.act(UiAction::Press("minus", 1));
        }
        if out.widget("segments +", ui.button("+")).clicked() {
            out.act(UiAction::Press("plus", 1));
        }
    });
    toggle(ui, out, "o", s.culling.enabled, "GPU culling");
    let lod = s.culling.density || s.culling.segment_lod || s.culling.solid_outline;
    toggle(ui, out, "y", lod, format!("LOD {:?}", s.culling.buckets()).as_str());
    toggle(ui, out, "z", view.frozen, "freeze the culling camera");
    match view.budget {
        Some((ms, scale)) => ui.label(format!("frame budget {ms} ms: LOD scale {scale:.2}")),
        None => ui.label("no frame budget (--budget-ms)"),
    };
}

/// Animation: model, evaluation placement, smoothing, wind, gusts, sources, colliders, calm areas.
pub fn animation(ui: &mut Ui, view: &UiView, out: &mut PanelOutput) {
    let a = view.animation;
    let mode = match (a.mode, view.settings.floor) {
        (_, true) => 3,
        (Mode::Static, _) => 0,
        (Mode::Texture, _) => 1,
        (Mode::Uniform, _) => 2,
    };
    cycle(ui, out, "m", &["static", "texture", "uniform", "floor"], mode);
    let smoothing = match a.smoothing {
        Smoothing::Nearest => 0,
        Smoothing::Linear => 1,
        Smoothing::Slerp => 2,
    };
    cycle(ui, out, "n", &["nearest", "linear", "slerp"], smoothing);
    cycle(ui, out, "b", &["per vertex", "per blade"], usize::from(a.eval == Eval::Blade));
    let global = a.wind.global;
    let (mut direction, mut strength) = global.map_or((0.0, 0.0), |g| (g.direction_deg, g.strength));
    let strength_slider = ui.add(egui::Slider::new(&mut strength, 0.0..=1.0).text("wind strength"));
    let direction_slider = ui.add(egui::Slider::new(&mut direction, -180.0..=180.0).text("wind direction"));
    let moved = out.widget("wind strength", strength_slider).changed()
        | out.widget("wind direction", direction_slider).changed();
    if moved {
        out.act(UiAction::Wind { direction_deg: direction, strength });
    }
    let mut gusts = global.is_some_and(|g| g.gusts);
    if out.widget("gusts", ui.checkbox(&mut gusts, "gusts")).changed() {
        out.act(UiAction::Gusts(gusts));
    }
    toggle(ui, out, "c", view.calm, &format!("calm areas ({})", a.wind.calm.len()));
    ui.label(format!("{} wind sources (left click drops one)", a.wind.sources.len()));
    for (i, source) in a.wind.sources.iter().enumerate() {
        ui.horizontal(|ui| {
            let mut power = source.power;
            let label = format!("#{i} at {:.1}, {:.1}", source.position.x, source.position.y);
            if ui.add(egui::Slider::new(&mut power, 0.0..=1.0).text(label)).changed() {
                out.act(UiAction::SourcePower(i, power));
            }
            if ui.small_button("x").clicked() {
                out.act(UiAction::RemoveSource(i));
            }
        });
    }
    for (i, c) in a.wind.colliders.iter().enumerate() {
        ui.horizontal(|ui| {
            ui.label(format!("collider #{i} at {:.1}, {:.1} (arrow keys)", c.center.x, c.center.z));
            if ui.small_button("x").clicked() {
                out.act(UiAction::RemoveCollider(i));
            }
        });
    }
}

/// View: debug views, wireframe, MSAA, pause, walking; presentation as started.
pub fn view(ui: &mut Ui, view: &UiView, out: &mut PanelOutput) {
    let s = view.settings;
    let debug = match (s.debug_lod, s.debug_tiles, s.debug_fresnel) {
        (true, _, _) => 1,
        (_, true, _) => 2,
        (_, _, true) => 3,
        _ => 0,
    };
    cycle(ui, out, "t", &["shaded", "LOD", "tiles", "Fresnel"], debug);
    toggle(ui, out, "v", s.debug_force, "force view");
    toggle(ui, out, "x", s.debug_bounds, "cluster bounds");
    toggle(ui, out, "f", s.wireframe, "wireframe");
    ui.horizontal(|ui| {
        let msaa = match s.msaa {
            m if !m.enabled() => "off".to_string(),
            m => format!("{}x {}", m.samples, if m.alpha_to_coverage { "alpha to coverage" } else { "alpha test" }),
        };
        ui.label(format!("MSAA {msaa}"));
        if out.widget("MSAA next", ui.button("next")).clicked() {
            out.act(UiAction::Press("r", 1));
        }
    });
    toggle(ui, out, "p", view.paused, "pause time");
    toggle(ui, out, "g", view.walk, "walk on the ground");
    ui.label(&view.presentation);
}
