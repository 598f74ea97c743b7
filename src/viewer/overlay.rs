//! The viewer's side of its overlay (`ui`): what the panels show, applying what they ask for
//! through the same paths as the keys, and the capture of a trace of the next frames.

use std::time::Instant;

use super::ui::{Ui, UiAction, UiView};
use super::Viewer;
use crate::error::{Error, Result};
use crate::render::FrameTimings;

/// A capture in progress: the trace of the next frames, for `--capture-dir`.
pub(super) struct Capture {
    wanted: usize,
    frames: Vec<(u32, FrameTimings)>,
    mapping: Option<crate::harness::timing::ClockMapping>,
    started: Instant,
}

impl Viewer {
    /// Make the overlay for the window (unless `--no-ui`).
    pub(super) fn make_ui(&mut self, window: &winit::window::Window) {
        if self.options.ui {
            self.ui = Some(Ui::new(window, self.device.limits().max_image_dimension2_d as usize));
        }
    }

    /// The frame in `slot` was begun: take the timings of its previous frame (statistics, frame
    /// budget, overlay graphs, capture), then give the renderer this frame's overlay.
    pub(super) fn frame_begun(&mut self, timings: Option<FrameTimings>, screenshot: bool) -> Result<()> {
        if let Some(t) = timings {
            self.stats.add(&t);
            if let Some(budget) = self.budget.as_mut() {
                self.renderer.as_mut().expect("renderer built").set_lod_scale(budget.update(t.gpu_ms));
            }
            self.add_timings(&t)?;
        }
        self.draw_overlay(screenshot)
    }

    /// Give the renderer this frame's overlay: none when hidden, or for a screenshot unless
    /// `--screenshot-ui`. The panels' actions are applied before the next frame.
    pub(super) fn draw_overlay(&mut self, screenshot: bool) -> Result<()> {
        let renderer = self.renderer.as_mut().expect("renderer built");
        let shown = !screenshot || self.options.screenshot_ui;
        let (Some(ui), Some(surface), true) = (self.ui.as_mut(), self.surface.as_ref(), shown) else {
            return renderer.set_overlay(None);
        };
        if !ui.visible {
            return renderer.set_overlay(None);
        }
        let scene = match &self.scene.field {
            Some(field) => format!(
                "{} field, {} blades/m²",
                field.spec.size.map_or("unbounded".to_string(), |s| format!("{s} m")),
                field.spec.density
            ),
            None => format!("{} blades", self.scene.blades.len()),
        };
        let o = &self.options;
        let view = UiView {
            settings: renderer.settings(),
            animation: renderer.animation(),
            scene,
            frozen: renderer.cull_camera().is_some(),
            paused: self.paused,
            slowed: self.clock.slowed().then_some(self.clock.clock().dt),
            walk: self.control.walk,
            trample: self.trample,
            slope_limit: (o.scene.landscape.slope_limit_deg.is_some(), self.slope_limit_deg),
            clumps: (o.scene.clumps.is_some(), self.clump_size_m),
            flowers: (o.scene.flowers.is_some(), self.flowers_per_m2),
            calm: self.calm_off.is_none(),
            budget: self.budget.as_ref().map(|b| (b.target_ms, b.scale)),
            present: (surface.swapchain.present_mode(), surface.swapchain.present_modes()),
            capture: match (&o.capture_dir, &self.capture) {
                (None, _) => Err("no capture: start with --capture-dir DIR"),
                (Some(_), Some(_)) => Err("capturing..."),
                (Some(_), None) => Ok(()),
            },
        };
        let (frame, actions) = ui.frame(&surface.window, &view);
        self.ui_actions.extend(actions);
        if screenshot {
            // Where the screenshot shows the overlay (pixels, within the picture: a panel taller
            // than the window at a large scale factor starts above it), for whoever compares it.
            let rects: Vec<String> = ui
                .panels
                .iter()
                .map(|r| r.map(|v| v.max(0.0)))
                .map(|r| format!("{:.0},{:.0},{:.0},{:.0}", r[0], r[1], r[2], r[3]))
                .collect();
            println!("overlay panels in the screenshot: {}", rects.join(" "));
        }
        renderer.set_overlay(Some(frame))
    }

    /// Apply what the panels asked for last frame.
    pub(super) fn apply_ui_actions(&mut self) -> Result<()> {
        for action in std::mem::take(&mut self.ui_actions) {
            match action {
                UiAction::Press(key, times) => {
                    for _ in 0..times {
                        self.key(key, true)?;
                        self.key(key, false)?;
                    }
                }
                UiAction::Wind { direction_deg, strength } => {
                    let wind = self.renderer.as_mut().expect("renderer built").wind_mut();
                    let global =
                        wind.global.get_or_insert(crate::wind::GlobalWind { direction_deg, strength, gusts: true });
                    (global.direction_deg, global.strength) = (direction_deg, strength);
                    println!("wind strength {strength:.2}, direction {direction_deg:.0} deg");
                }
                UiAction::Gusts(on) => {
                    let wind = self.renderer.as_mut().expect("renderer built").wind_mut();
                    if let Some(global) = wind.global.as_mut() {
                        global.gusts = on;
                        println!("gusts {}", if on { "on" } else { "off" });
                    }
                }
                UiAction::SourcePower(i, power) => {
                    let wind = self.renderer.as_mut().expect("renderer built").wind_mut();
                    if let Some(source) = wind.sources.get_mut(i) {
                        source.power = power;
                    }
                }
                UiAction::RemoveSource(i) => self.remove_emitter(i, true),
                UiAction::RemoveCollider(i) => self.remove_emitter(i, false),
                UiAction::AddCalm => {
                    let p = self.control.camera.position;
                    let at = glam::Vec2::new(p.x, p.z);
                    let area = crate::wind::CalmArea { min: at - 2.0, max: at + 2.0 };
                    self.renderer.as_mut().expect("renderer built").wind_mut().calm.push(area);
                    println!("calm area {:.1}, {:.1} to {:.1}, {:.1}", area.min.x, area.min.y, area.max.x, area.max.y);
                }
                UiAction::RemoveCalm(i) => {
                    let calm = &mut self.renderer.as_mut().expect("renderer built").wind_mut().calm;
                    if i < calm.len() {
                        calm.remove(i);
                        println!("calm area #{i} removed");
                    }
                }
                UiAction::Capture(frames) => self.start_capture(frames as usize)?,
                UiAction::Culling(culling) => {
                    let animation = self.renderer.as_ref().expect("renderer built").animation().clone();
                    let settings = crate::render::RenderSettings { culling, ..self.settings };
                    if self.rebuild_passes("the culling settings", settings, animation)? {
                        println!("culling {:?}", self.settings.culling);
                    }
                }
                UiAction::LodScale(scale) => self.renderer.as_mut().expect("renderer built").set_lod_scale(scale),
                UiAction::Fog(density) => {
                    self.settings.fog_density = density;
                    self.renderer.as_mut().expect("renderer built").set_fog_density(density);
                }
                UiAction::Budget(target) => self.set_budget(target)?,
                UiAction::ClumpSize(size_m) => self.set_clump_size(size_m)?,
                UiAction::FlowerDensity(per_m2) => self.set_flower_density(per_m2)?,
                UiAction::Present(mode) => {
                    let surface = self.surface.as_mut().expect("surface exists");
                    surface.swapchain.set_present_mode(mode)?;
                    self.options.present = mode;
                    self.needs_recreate = true;
                    println!("present mode {mode:?}");
                }
                UiAction::FramesInFlight(frames_in_flight) => self.set_frames_in_flight(frames_in_flight)?,
            }
        }
        Ok(())
    }

    /// F1: hide or show the overlay.
    pub(super) fn toggle_overlay(&mut self) {
        if let Some(ui) = self.ui.as_mut() {
            ui.visible = !ui.visible;
            println!("overlay {}", if ui.visible { "shown" } else { "hidden" });
        }
    }

    /// A script's pointer input to the overlay (refused without one).
    pub(super) fn scripted_ui(&mut self, act: impl FnOnce(&mut Ui) -> Result<()>) -> Result<()> {
        match self.ui.as_mut() {
            Some(ui) if ui.visible => act(ui),
            _ => Err(Error::bad_input(
                "--script: ui-click and ui-drag need the overlay shown (not --no-ui, not hidden by F1)",
            )),
        }
    }

    /// Hold the GPU frame near `target` ms, or stop (the LOD scale stays where it is).
    fn set_budget(&mut self, target: Option<f32>) -> Result<()> {
        crate::app::check_timestamps_for_budget(&self.device, target)?;
        let scale = self.renderer.as_ref().expect("renderer built").settings().culling.lod_scale;
        self.budget = target.map(|ms| crate::render::budget::FrameBudget::new(ms, scale));
        println!("frame budget {}", target.map_or("off".to_string(), |ms| format!("{ms:.0} ms")));
        Ok(())
    }

    fn remove_emitter(&mut self, i: usize, source: bool) {
        let wind = self.renderer.as_mut().expect("renderer built").wind_mut();
        if source && i < wind.sources.len() {
            wind.sources.remove(i);
        } else if !source && i < wind.colliders.len() {
            wind.colliders.remove(i);
        }
    }

    fn start_capture(&mut self, wanted: usize) -> Result<()> {
        let renderer = self.renderer.as_mut().expect("renderer built");
        let mapping = crate::harness::trace::calibrated(&self.device, renderer)?;
        self.capture = Some(Capture { wanted, frames: Vec::new(), mapping, started: Instant::now() });
        println!("capturing {wanted} frames");
        Ok(())
    }

    /// A frame's timings: into the overlay's graphs, and into the capture in progress (written
    /// once it has its frames).
    pub(super) fn add_timings(&mut self, timings: &FrameTimings) -> Result<()> {
        if let Some(ui) = self.ui.as_mut() {
            ui.add_timings(timings);
        }
        let Some(capture) = self.capture.as_mut() else { return Ok(()) };
        // Only frames submitted after the capture began.
        if timings.cpu_spans.is_some_and(|[started, _, _]| started >= capture.started) {
            capture.frames.push((capture.frames.len() as u32, timings.clone()));
        }
        if capture.frames.len() < capture.wanted {
            return Ok(());
        }
        let capture = self.capture.take().expect("a capture");
        let dir =
            self.options.capture_dir.as_ref().ok_or_else(|| Error::Internal("capture without a directory".into()))?;
        let span = (capture.started, Instant::now());
        let trace =
            crate::harness::trace::of_frames(capture.frames, self.options.frames_in_flight, capture.mapping, span)?;
        self.captures_written += 1;
        let path = dir.join(format!("meadow-capture-{}.json", self.captures_written));
        crate::app::write_text(&path, &serde_json::to_string(&trace).expect("serialises"))?;
        println!("wrote {}", path.display());
        Ok(())
    }
}
