//! The viewer's overlay (issue 12): egui panels with every control and live GPU timing, shown by
//! default (F1 toggles it, `--no-ui` leaves it out). egui-winit turns window events into egui's
//! input; the renderer draws egui's triangles with a pass of its own (`render::overlay`), after
//! the scene, with its own timestamp. Scripts click and drag the controls by label, delivered as
//! pointer events through egui's input like a mouse's.

mod panels;
mod timing;

use std::collections::VecDeque;

use winit::event::WindowEvent;
use winit::window::Window;

use panels::PanelOutput;
pub use panels::{UiAction, UiView};
pub use timing::TimingHistory;

use crate::error::{Error, Result};
use crate::render::overlay::OverlayFrame;
use crate::render::FrameTimings;

/// The overlay's state between frames.
pub struct Ui {
    ctx: egui::Context,
    input: egui_winit::State,
    /// Shown (F1 toggles).
    pub visible: bool,
    history: TimingHistory,
    /// Pointer events a script asked for, one batch per frame.
    scripted: VecDeque<Vec<egui::Event>>,
    /// Where each labelled control was drawn last frame (points).
    widgets: Vec<(String, egui::Rect)>,
    /// The panels' rectangles last frame, in pixels (x0, y0, x1, y1).
    pub panels: Vec<[f32; 4]>,
    /// Every texture egui has set, as it now stands: egui sends a texture once, so a new
    /// renderer (a new blade count) is given them all again.
    textures: std::collections::HashMap<egui::TextureId, egui::epaint::ImageDelta>,
    /// The renderer was replaced: resend every texture with the next frame.
    resend: bool,
}

impl Ui {
    /// The overlay of `window`, for textures up to `max_texture_side` texels.
    pub fn new(window: &Window, max_texture_side: usize) -> Self {
        let ctx = egui::Context::default();
        // No shadows: the panels cover exactly their rectangles (and draw fewer blended pixels).
        ctx.style_mut(|style| {
            style.visuals.window_shadow = egui::Shadow::NONE;
            style.visuals.popup_shadow = egui::Shadow::NONE;
        });
        let input = egui_winit::State::new(
            ctx.clone(),
            egui::ViewportId::ROOT,
            window,
            Some(window.scale_factor() as f32),
            None,
            Some(max_texture_side),
        );
        Self {
            ctx,
            input,
            visible: true,
            history: TimingHistory::default(),
            scripted: VecDeque::new(),
            widgets: Vec::new(),
            panels: Vec::new(),
            textures: std::collections::HashMap::new(),
            resend: false,
        }
    }

    /// A window event: true when egui takes it (a click on a control is not also a click into
    /// the scene). A hidden overlay takes nothing.
    pub fn on_event(&mut self, window: &Window, event: &WindowEvent) -> bool {
        let response = self.input.on_window_event(window, event);
        self.visible && response.consumed
    }

    /// Keep a frame's timings for the graph and percentiles.
    pub fn add_timings(&mut self, timings: &FrameTimings) {
        self.history.add(timings);
    }

    /// The scripted click of control `label`: pointer press, then release next frame.
    pub fn click(&mut self, label: &str) -> Result<()> {
        let at = self.find(label)?.center();
        self.scripted.push_back(vec![egui::Event::PointerMoved(at), press(at, true)]);
        self.scripted.push_back(vec![press(at, false)]);
        Ok(())
    }

    /// The scripted drag of control `label` by `dx` pixels to the right (a slider).
    pub fn drag(&mut self, label: &str, dx: f32) -> Result<()> {
        let from = self.find(label)?.center();
        let to = from + egui::vec2(dx / self.ctx.pixels_per_point(), 0.0);
        self.scripted.push_back(vec![egui::Event::PointerMoved(from), press(from, true)]);
        self.scripted.push_back(vec![egui::Event::PointerMoved(to)]);
        self.scripted.push_back(vec![press(to, false)]);
        Ok(())
    }

    /// Where control `label` (or the one control whose label starts with it) was drawn.
    fn find(&self, label: &str) -> Result<egui::Rect> {
        let exact = self.widgets.iter().find(|(l, _)| l == label);
        let mut prefixed = self.widgets.iter().filter(|(l, _)| l.starts_with(label));
        let found = exact.or_else(|| prefixed.next().filter(|_| prefixed.next().is_none()));
        found.map(|(_, rect)| *rect).ok_or_else(|| {
            let known: Vec<&str> = self.widgets.iter().map(|(l, _)| l.as_str()).collect();
            Error::bad_input(format!(
                "--script: no control '{}' on screen (shown: {})",
                crate::error::quoted(label),
                known.join(", ")
            ))
        })
    }

    /// Run egui for this frame over `view`: what to draw, and the actions the controls asked for.
    pub fn frame(&mut self, window: &Window, view: &UiView) -> (OverlayFrame, Vec<UiAction>) {
        let mut raw = self.input.take_egui_input(window);
        if let Some(batch) = self.scripted.pop_front() {
            raw.events.extend(batch);
        }
        let mut out = PanelOutput::default();
        let ctx = self.ctx.clone();
        let history = &self.history;
        let mut panels = Vec::new();
        let full = ctx.run(raw, |ctx| panels = show(ctx, view, history, &mut out));
        self.input.handle_platform_output(window, full.platform_output);
        let ppp = full.pixels_per_point;
        self.panels = panels.iter().map(|r| [r.min.x * ppp, r.min.y * ppp, r.max.x * ppp, r.max.y * ppp]).collect();
        // A control past the window's edge cannot be clicked: scripts are told it is not shown.
        let screen = ctx.content_rect();
        self.widgets = out.widgets.into_iter().filter(|(_, r)| screen.contains(r.center())).collect();
        let primitives = ctx.tessellate(full.shapes, ppp);
        let textures = self.keep_textures(full.textures_delta);
        (OverlayFrame { primitives, textures, pixels_per_point: ppp }, out.actions)
    }

    /// The renderer was replaced (its textures went with it).
    pub fn renderer_replaced(&mut self) {
        self.resend = true;
    }

    /// Keep a copy of what `delta` sets, and return what to give the renderer: `delta`, after
    /// every texture in full when the renderer was replaced.
    fn keep_textures(&mut self, delta: egui::TexturesDelta) -> egui::TexturesDelta {
        let mut given = egui::TexturesDelta::default();
        if std::mem::take(&mut self.resend) {
            given.set.extend(self.textures.iter().map(|(id, image)| (*id, image.clone())));
        }
        for (id, image) in &delta.set {
            match (image.pos, self.textures.get_mut(id)) {
                (Some(pos), Some(kept)) => patch(kept, image, pos),
                _ => {
                    self.textures.insert(*id, image.clone());
                }
            }
        }
        for id in &delta.free {
            self.textures.remove(id);
        }
        given.set.extend(delta.set);
        given.free.extend(delta.free);
        given
    }

    /// Pointer events of a script still to be delivered.
    pub fn scripted_pending(&self) -> bool {
        !self.scripted.is_empty()
    }
}

/// Copy `region`'s texels into `kept` (a whole texture) at `pos`.
fn patch(kept: &mut egui::epaint::ImageDelta, region: &egui::epaint::ImageDelta, pos: [usize; 2]) {
    let (egui::ImageData::Color(whole), egui::ImageData::Color(part)) = (&mut kept.image, &region.image);
    let whole = std::sync::Arc::make_mut(whole);
    let [w, _] = whole.size;
    for (row, texels) in part.pixels.chunks(part.size[0].max(1)).enumerate() {
        let start = (pos[1] + row) * w + pos[0];
        if let Some(target) = whole.pixels.get_mut(start..start + texels.len()) {
            target.copy_from_slice(texels);
        }
    }
}

/// The primary button pressed or released at `at`.
fn press(at: egui::Pos2, pressed: bool) -> egui::Event {
    egui::Event::PointerButton { pos: at, button: egui::PointerButton::Primary, pressed, modifiers: Default::default() }
}

/// The panels: the scene and animation controls (top left), GPU timing (top right), the view
/// (bottom right); returns their rectangles (points). None scrolls, so a control stays where it
/// was drawn (scripts click by label).
fn show(ctx: &egui::Context, view: &UiView, history: &TimingHistory, out: &mut PanelOutput) -> Vec<egui::Rect> {
    let controls = egui::Window::new("meadow").default_pos([8.0, 8.0]).default_width(300.0).show(ctx, |ui| {
        egui::CollapsingHeader::new("Scene").default_open(true).show(ui, |ui| panels::scene(ui, view, out));
        egui::CollapsingHeader::new("Animation").default_open(true).show(ui, |ui| panels::animation(ui, view, out));
    });
    let view_panel = egui::Window::new("view")
        .anchor(egui::Align2::RIGHT_BOTTOM, [-8.0, -8.0])
        .default_width(360.0)
        .show(ctx, |ui| panels::view(ui, view, out));
    let timing = egui::Window::new("GPU timing")
        .anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0])
        .default_width(360.0)
        .show(ctx, |ui| {
            history.show(ui);
            match view.capture {
                Ok(()) => {
                    let button = ui.button("capture a trace of the next 60 frames");
                    if out.widget("capture", button).clicked() {
                        out.act(UiAction::Capture(60));
                    }
                }
                Err(why) => {
                    ui.label(why);
                }
            }
        });
    [controls, timing, view_panel].into_iter().flatten().map(|w| w.response.rect).collect()
}
