//! The viewer's event loop: window events, one tick per loop iteration (script actions, camera,
//! a frame) and the exit screenshot.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::keyboard::PhysicalKey;
use winit::window::WindowId;

use super::keys::key_name;
use super::script::Action;
use super::Viewer;
use crate::error::{Error, Result};

impl Viewer {
    /// One loop iteration: script actions, camera, and a frame unless minimised.
    pub(super) fn tick(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        for action in self.script.due(self.tick) {
            self.act(action)?;
        }
        self.apply_ui_actions()?;
        self.tick += 1;
        let now = Instant::now();
        let elapsed = (now - self.last_tick).as_secs_f64();
        let dt = if self.fixed_step { 1.0 / 60.0 } else { elapsed.min(0.1) as f32 };
        self.last_tick = now;
        let scene = &self.scene;
        self.control.update(dt, |x, z| scene.ground(x, z));
        // The simulation in whole steps of --dt: one a tick in a script's fixed-step run (the same
        // frames on every machine), else as real time passes, at most 4 a frame.
        match (self.paused, self.fixed_step) {
            (true, _) => {}
            (false, true) => self.clock.step(),
            (false, false) => {
                self.clock.advance(elapsed);
            }
        }
        let surface = self.surface.as_ref().expect("surface exists");
        let size = surface.window.inner_size();
        let minimised = size.width == 0 || size.height == 0 || surface.window.is_minimized() == Some(true);
        if minimised {
            // Nothing to draw into: sleep until an event or the next script tick, no busy loop.
            self.minimised = true;
            event_loop.set_control_flow(ControlFlow::WaitUntil(now + Duration::from_millis(50)));
            return Ok(());
        }
        if self.minimised {
            self.minimised = false;
            self.needs_recreate = true;
        }
        event_loop.set_control_flow(ControlFlow::Poll);
        // F7's sphere under the eye, for this frame only (the panel and keys see the wind without it).
        let trampler = self.trampler();
        if let Some(sphere) = trampler {
            self.renderer.as_mut().expect("renderer built").wind_mut().colliders.push(sphere);
        }
        let rendered = self.render();
        if trampler.is_some() {
            self.renderer.as_mut().expect("renderer built").wind_mut().colliders.pop();
        }
        rendered?;
        if self.options.frames.is_some_and(|n| self.frames >= n)
            || (self.options.script.is_some()
                && self.script.is_empty()
                && !self.ui.as_ref().is_some_and(|ui| ui.scripted_pending())
                && self.options.frames.is_none())
        {
            self.quit = true;
        }
        Ok(())
    }

    pub(super) fn act(&mut self, action: Action) -> Result<()> {
        let window = &self.surface.as_ref().expect("surface exists").window;
        match action {
            Action::Camera(camera) => self.control.camera = camera,
            Action::Time(t) => self.clock.jump(t.into()),
            Action::Pause => self.paused = !self.paused,
            Action::Key(name, pressed) => self.key(&name, pressed)?,
            Action::Press(name) => {
                self.key(&name, true)?;
                self.key(&name, false)?;
            }
            Action::Click(x, y) => {
                self.click(x, y);
                self.dragging = false;
            }
            Action::Collider(collider) => self.add_collider(collider)?,
            Action::MoveCollider(index, at) => self.move_collider(index, at)?,
            Action::Resize(w, h) => {
                // What the device cannot render at (its largest image, the multisampled images'
                // maxResourceSize, the budget) no swapchain can follow: refused, like --size.
                let blades = self.scene.blades.len() as u32;
                let cells = crate::scene::Terrain::cells_for(crate::scene::blades::field_size(blades));
                crate::app::check_limits(
                    &self.device,
                    blades,
                    ((w, h), self.settings.msaa, self.settings.linear_scene()),
                    cells,
                )
                .map_err(|e| Error::bad_input(format!("--script: resize {w}x{h}: {e}")))?;
                let _ = window.request_inner_size(PhysicalSize::new(w, h));
                self.needs_recreate = true;
            }
            Action::Minimise => window.set_minimized(true),
            Action::Restore => {
                window.set_minimized(false);
                self.needs_recreate = true;
            }
            Action::Screenshot(path) => self.screenshot = Some(PathBuf::from(path)),
            Action::UiClick(label) => self.scripted_ui(|ui| ui.click(&label))?,
            Action::UiDrag(dx, label) => self.scripted_ui(|ui| ui.drag(&label, dx))?,
            Action::Quit => self.quit = true,
        }
        Ok(())
    }
}

impl ApplicationHandler for Viewer {
    /// The window exists before the viewer (`session`).
    fn resumed(&mut self, _: &ActiveEventLoop) {}

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        // The overlay sees every event first; one it takes (a click on a control) goes no further.
        if let (Some(ui), Some(surface)) = (self.ui.as_mut(), self.surface.as_ref()) {
            let passes_through = matches!(event, WindowEvent::CloseRequested | WindowEvent::Resized(_));
            if ui.on_event(&surface.window, &event) && !passes_through {
                return;
            }
        }
        let result = match event {
            WindowEvent::CloseRequested => {
                self.quit = true;
                Ok(())
            }
            WindowEvent::Resized(_) => {
                self.needs_recreate = true;
                Ok(())
            }
            WindowEvent::KeyboardInput { event, .. } => match (event.physical_key, event.repeat) {
                (PhysicalKey::Code(code), false) => match key_name(code) {
                    Some(name) => self.key(name, event.state == ElementState::Pressed),
                    None => Ok(()),
                },
                _ => Ok(()),
            },
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                self.control.cursor(position.x, position.y);
                if self.dragging {
                    if let Some(hit) = self.pick(position.x, position.y) {
                        if let Some(source) = self.renderer.as_mut().and_then(|r| r.wind_mut().sources.last_mut()) {
                            source.position = hit;
                        }
                    }
                }
                Ok(())
            }
            WindowEvent::MouseInput { state, button, .. } => {
                let pressed = state == ElementState::Pressed;
                match button {
                    MouseButton::Right => self.control.look_button(pressed),
                    MouseButton::Left if pressed => self.click(self.cursor.0, self.cursor.1),
                    MouseButton::Left => self.dragging = false,
                    _ => {}
                }
                Ok(())
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let steps = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.control.wheel(steps);
                Ok(())
            }
            _ => Ok(()),
        };
        if let Err(e) = result {
            self.fail(event_loop, e);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.surface.is_none() || self.error.is_some() {
            return;
        }
        // A signal (Ctrl-C, SIGTERM, SIGHUP) ends the session at once, without the exit
        // screenshot: nothing is written after it (`app::interrupt`).
        if let Err(e) = crate::app::interrupt::check() {
            self.fail(event_loop, e);
            return;
        }
        if !self.quit {
            if let Err(e) = self.tick(event_loop) {
                self.fail(event_loop, e);
                return;
            }
        }
        if self.quit {
            if let Some(path) = self.options.screenshot.take() {
                // The exit screenshot: one more frame, written to the file.
                self.screenshot = Some(path.clone());
                // An injected out-of-date result takes a call without a frame: one more try.
                let rendered = self.render().and_then(|()| match self.screenshot.is_some() && self.injected_last {
                    true => self.render(),
                    false => Ok(()),
                });
                let rendered = rendered.and_then(|()| match self.screenshot {
                    Some(_) => Err(Error::Environment(format!(
                        "--screenshot {}: the window has no area (minimised), nothing to capture",
                        path.display()
                    ))),
                    None => Ok(()),
                });
                if let Err(e) = rendered {
                    self.fail(event_loop, e);
                    return;
                }
            }
            event_loop.exit();
        }
    }
}
