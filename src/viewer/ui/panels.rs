//! The overlay's control panels: everything the keys and flags reach (scene, animation, view).
//! A widget does not change the viewer itself: it returns [`UiAction`]s, which the viewer applies
//! through the same paths as its keys (a rebuild that fails is reported and undone the same way).

use egui::Ui;

use crate::keyframes::Smoothing;
use crate::render::animation::sine::SinePhase;
use crate::render::animation::{AnimationSettings, Eval, Mode};
use crate::render::culling::Culling;
use crate::render::RenderSettings;
use crate::vk::swapchain::PresentMode;

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
    /// Add a 4 m calm area centred under the camera.
    AddCalm,
    /// Remove calm area `index`.
    RemoveCalm(usize),
    /// Write the trace of the next `frames` frames into `--capture-dir`.
    Capture(u32),
    /// Cull and LOD with these settings (tests, LOD kinds, view distance): passes rebuilt.
    Culling(Culling),
    /// The LOD scale (no rebuild; the frame budget sets it when there is one).
    LodScale(f32),
    /// The fog's density per metre (no rebuild).
    Fog(f32),
    /// Blades in clumps of this size (m): a new scene and renderer.
    ClumpSize(f32),
    /// Flowers at this density (per m²): a new scene and renderer.
    FlowerDensity(f32),
    /// Hold the GPU frame near this many ms (`--budget-ms`), or stop.
    Budget(Option<f32>),
    /// Present with this mode (the swapchain is re-created).
    Present(PresentMode),
    /// Frames in flight (a new renderer).
    FramesInFlight(usize),
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
    /// The last frame wanted more than 4 steps of this many seconds: simulated time slows.
    pub slowed: Option<f64>,
    /// The camera walks on the ground (G).
    pub walk: bool,
    /// A sphere under the eye tramples the grass (F7).
    pub trample: bool,
    /// Calm areas are on (C).
    pub calm: bool,
    /// The slope limit is on (F4), and its degrees.
    pub slope_limit: (bool, f32),
    /// Blades are in clumps (F5), and their size (m).
    pub clumps: (bool, f32),
    /// Flowers are drawn (F6), and their density (per m²).
    pub flowers: (bool, f32),
    /// `--budget-ms` and the LOD scale it sets.
    pub budget: Option<(f32, f32)>,
    /// The present mode and those the surface supports.
    pub present: (PresentMode, Vec<PresentMode>),
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
    if s.culling.enabled {
        culling(ui, s.culling, out);
    }
    budget(ui, view, out);
}

/// The cull's tests and LOD kinds, one checkbox each, the view distance and the blade distance
/// (blades end at the shorter of the two, `Culling::blade_range`).
fn culling(ui: &mut Ui, c: Culling, out: &mut PanelOutput) {
    // While a distance slider is dragged, the panel draws the dragged settings, kept in egui's
    // memory from frame to frame; they apply when the drag ends (a rebuild per dragged step would
    // be slow). Drawn from the renderer's settings, the slider sprang back each frame and a drag
    // applied nothing.
    let draft = egui::Id::new("culling settings while a distance is dragged");
    let mut next = ui.data(|d| d.get_temp::<Culling>(draft)).unwrap_or(c);
    ui.horizontal_wrapped(|ui| {
        ui.label("cull:");
        for (label, on) in [
            ("frustum", &mut next.frustum),
            ("distance", &mut next.distance),
            ("orientation", &mut next.orientation),
            ("occlusion", &mut next.occlusion),
        ] {
            out.widget(label, ui.checkbox(on, label));
        }
    });
    ui.horizontal_wrapped(|ui| {
        ui.label("LOD:");
        for (label, on) in [
            ("density", &mut next.density),
            ("segment buckets", &mut next.segment_lod),
            ("outline as geometry", &mut next.solid_outline),
        ] {
            out.widget(label, ui.checkbox(on, label));
        }
    });
    let most = crate::render::limits::MAX_VIEW_DISTANCE;
    let distance = egui::Slider::new(&mut next.view_distance, 10.0..=most).logarithmic(true).text("view distance m");
    let slider = out.widget("view distance m", ui.add(distance));
    let blades = egui::Slider::new(&mut next.blade_distance, 5.0..=crate::render::field_gpu::max_blade_distance())
        .logarithmic(true)
        .text("blade distance m");
    let blade_slider = out.widget("blade distance m", ui.add(blades));
    ui.horizontal(|ui| {
        use crate::render::far_field::FarField;
        ui.label("far field:");
        for (id, label, mesh) in [
            ("far field billboards", "billboards", FarField::Billboards),
            ("far field stars", "stars", FarField::Stars),
            ("far field off", "off", FarField::Off),
        ] {
            out.widget(id, ui.radio_value(&mut next.far_field, mesh, label));
        }
    });
    ui.horizontal(|ui| {
        use crate::render::far_field::FarFade;
        ui.label("fade:");
        for (id, label, fade) in [("fade dither", "dither", FarFade::Dither), ("fade blend", "blend", FarFade::Blend)] {
            out.widget(id, ui.radio_value(&mut next.far_fade, fade, label));
        }
    });
    if slider.dragged() || blade_slider.dragged() {
        ui.data_mut(|d| d.insert_temp(draft, next));
        return;
    }
    ui.data_mut(|d| d.remove::<Culling>(draft));
    if next != c {
        out.act(UiAction::Culling(next));
    }
}

/// The frame budget (on, its target) or, without one, the LOD scale.
fn budget(ui: &mut Ui, view: &UiView, out: &mut PanelOutput) {
    let mut on = view.budget.is_some();
    let (mut ms, scale) = view.budget.unwrap_or((50.0, view.settings.culling.lod_scale));
    if out.widget("frame budget", ui.checkbox(&mut on, "frame budget")).changed() {
        out.act(UiAction::Budget(on.then_some(ms)));
    }
    if on {
        let target = egui::Slider::new(&mut ms, 5.0..=500.0).logarithmic(true).text("target GPU ms");
        if out.widget("target GPU ms", ui.add(target)).changed() {
            out.act(UiAction::Budget(Some(ms)));
        }
        ui.label(format!("LOD scale {scale:.2} (set by the budget)"));
    } else {
        let mut lod_scale = scale;
        let slider = egui::Slider::new(&mut lod_scale, 0.25..=2.0).text("LOD scale");
        if out.widget("LOD scale", ui.add(slider)).changed() {
            out.act(UiAction::LodScale(lod_scale));
        }
    }
}

/// The `m` key's cycle of blade responses (and the floor), and where the view is in it.
fn modes(view: &UiView) -> ([&'static str; 10], usize) {
    let mode = match (view.animation.mode, view.settings.floor) {
        (_, true) => 9,
        (Mode::Static, _) => 0,
        (Mode::Texture, _) => 1,
        (Mode::Uniform, _) => 2,
        (Mode::Sine(SinePhase::Object), _) => 3,
        (Mode::Sine(SinePhase::Vertex), _) => 4,
        (Mode::Sine(SinePhase::Cluster), _) => 5,
        (Mode::Verlet, _) => 6,
        (Mode::Inertial, _) => 7,
        (Mode::VirtualInertial, _) => 8,
    };
    let modes = [
        "static",
        "texture",
        "uniform",
        "sine per object",
        "sine per vertex",
        "sine per cluster",
        "verlet",
        "inertial",
        "virtual-inertial",
        "floor",
    ];
    (modes, mode)
}

/// Animation: model, evaluation placement, smoothing, wind, gusts, sources, colliders, calm areas.
pub fn animation(ui: &mut Ui, view: &UiView, out: &mut PanelOutput) {
    let a = view.animation;
    let (modes, mode) = modes(view);
    cycle(ui, out, "m", &modes, mode);
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
    use crate::render::wind::FieldKind;
    let field = [FieldKind::Analytic, FieldKind::Perlin, FieldKind::Fluid].iter().position(|k| *k == a.wind_field);
    cycle(ui, out, "f2", &["analytic wind", "perlin wind", "fluid wind"], field.unwrap_or(0));
    let mut gusts = global.is_some_and(|g| g.gusts);
    if out.widget("gusts", ui.checkbox(&mut gusts, "gusts")).changed() {
        out.act(UiAction::Gusts(gusts));
    }
    toggle(ui, out, "c", view.calm, &format!("calm areas ({})", a.wind.calm.len()));
    if view.calm {
        for (i, area) in a.wind.calm.iter().enumerate() {
            ui.horizontal(|ui| {
                ui.label(format!(
                    "calm #{i}: {:.1}, {:.1} to {:.1}, {:.1}",
                    area.min.x, area.min.y, area.max.x, area.max.y
                ));
                if out.widget(&format!("remove calm #{i}"), ui.small_button("x")).clicked() {
                    out.act(UiAction::RemoveCalm(i));
                }
            });
        }
        if out.widget("add a calm area here", ui.button("add a calm area here")).clicked() {
            out.act(UiAction::AddCalm);
        }
    }
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
    let debug = match (s.debug_lod, s.debug_tiles, s.debug_fresnel, s.debug_cover, s.debug_far) {
        (true, ..) => 1,
        (_, true, ..) => 2,
        (_, _, true, ..) => 3,
        (_, _, _, true, _) => 4,
        (.., true) => 5,
        _ => 0,
    };
    cycle(ui, out, "t", &["shaded", "LOD", "tiles", "Fresnel", "cover", "far field"], debug);
    toggle(ui, out, "v", s.debug_force, "force view");
    toggle(ui, out, "x", s.debug_bounds, "cluster bounds");
    toggle(ui, out, "f3", s.debug_wind, "wind arrows");
    let interaction = usize::from(s.debug_pressed) + 2 * usize::from(s.debug_patches && !s.debug_pressed);
    cycle(ui, out, "f8", &["no interaction view", "pressed (trails, cuts)", "patches"], interaction);
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
    let mut fog = s.fog_density;
    let slider = egui::Slider::new(&mut fog, 0.0..=0.05).text("fog per m");
    if out.widget("fog per m", ui.add(slider)).changed() {
        out.act(UiAction::Fog(fog));
    }
    toggle(ui, out, "p", view.paused, "pause time");
    if let Some(dt) = view.slowed {
        let steps = crate::render::animation::clock::MAX_STEPS_PER_FRAME;
        ui.label(format!("simulation slowed: {steps} steps of {:.1} ms a frame at most", dt * 1e3));
    }
    toggle(ui, out, "g", view.walk, "walk on the ground");
    toggle(ui, out, "f7", view.trample, "trample as I walk");
    let (on, degrees) = view.slope_limit;
    toggle(ui, out, "f4", on, &format!("slope limit {degrees}° (steep ground bare)"));
    let (on, mut size) = view.clumps;
    ui.horizontal(|ui| {
        toggle(ui, out, "f5", on, "clumps");
        let slider = egui::Slider::new(&mut size, 0.5..=5.0).text("m");
        if out.widget("clump size", ui.add(slider)).drag_stopped() {
            out.act(UiAction::ClumpSize(size));
        }
    });
    let (on, mut per_m2) = view.flowers;
    ui.horizontal(|ui| {
        toggle(ui, out, "f6", on, "flowers");
        let slider = egui::Slider::new(&mut per_m2, 1.0..=100.0).text("per m²");
        if out.widget("flower density", ui.add(slider)).drag_stopped() {
            out.act(UiAction::FlowerDensity(per_m2));
        }
    });
    let (present, supported) = &view.present;
    ui.horizontal(|ui| {
        for mode in supported {
            let label = format!("{mode:?}");
            if out.widget(&label, ui.selectable_label(mode == present, &label)).clicked() && mode != present {
                out.act(UiAction::Present(*mode));
            }
        }
    });
    ui.horizontal(|ui| {
        ui.label("frames in flight");
        for n in 1..=3usize {
            let label = format!("{n} in flight");
            let chosen = n == view.settings.frames_in_flight;
            if out.widget(&label, ui.selectable_label(chosen, n.to_string())).clicked() && !chosen {
                out.act(UiAction::FramesInFlight(n));
            }
        }
    });
}
