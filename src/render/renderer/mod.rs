//! The renderer, a facade: build it (`new`: the scene uploaded, the passes in a graph, the frames
//! in flight), then render frames into any [`TargetView`] — an offscreen image for
//! `meadow render`, a swapchain image for the viewer — with `render_offscreen`, or
//! `begin_frame` + `submit_frame`. The passes, their barriers and their timings are the graph's
//! (`render::graph`); fences, per-frame buffers, queries and deferred deletion are the frame
//! ring's (`render::frame`).

mod configuration;
mod extensions;
mod inspect;
mod multisample;
mod offscreen;
mod overlay;
mod passes;
mod record;
mod response;
mod uniforms;
mod wind;

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;

use ash::vk;

use crate::error::{Error, Result};
use crate::render::animation::poses::PoseRecords;
use crate::render::animation::pressed::PressedMap;
use crate::render::animation::response::{BladeResponse, ResponseStep};
use crate::render::animation::{self, AnimationSettings};
pub use crate::render::frame::{Deletion, FrameSync, FrameTimings, PassTime};
use crate::render::frame::{Frame, FrameRing, FrameUniforms, PerFrame};
use crate::render::graph::{Graph, Outputs, DEFAULT_DT};
use crate::render::layouts::{scene_frames, scene_layouts, SceneFrame, SceneLayouts};
use crate::render::msaa::{self, MultisampleTarget};
use crate::render::overlay::OverlayGpu;
use crate::render::passes::cull::CullFrame;
use crate::render::scene_gpu::SceneGpu;
use crate::render::settings::{check_pose_records, check_submission, polygon_mode};
pub use crate::render::settings::{
    RenderSettings, BLADES_PER_INSTANCE_RANGE, DEFAULT_BLADES_PER_INSTANCE, SEGMENTS_RANGE,
};
use crate::render::target::TargetView;
use crate::render::wind::{FrameForces, WindField};
use crate::scene::{field::check_camera, Camera, Scene};
use crate::vk::descriptor::Resource as Descriptor;
use crate::vk::{Destroy, Device, Resource};
pub use extensions::FrameInstance;
pub use response::Models;
use response::{Builders, RetiredResponse};

/// What set 0 of frame `slot` points at besides the scene and the frame's uniforms: that frame's
/// forces.
fn frame_bindings(forces: &PerFrame<FrameForces>, slot: usize) -> Vec<(&'static str, Descriptor)> {
    forces[slot].scene_resources().to_vec()
}

/// The scene on the GPU, its passes in a graph, and the frames in flight: build, then render
/// frames into any target. Every object it owns is destroyed on drop, after the device is idle.
pub struct Renderer {
    device: Arc<Device>,
    settings: RenderSettings,
    animation: AnimationSettings,
    scene: Option<SceneGpu>,
    /// The blade response (`render::animation::response`) and what builds it.
    response: Option<Box<dyn BladeResponse>>,
    builders: Builders,
    /// The names of the response's own passes in the graph (`Renderer::response_passes`).
    response_passes: Vec<&'static str>,
    /// The pose records it writes, if it poses blades once per blade, and set `SET_POSES`.
    poses: Option<PoseRecords>,
    layouts: SceneLayouts,
    graph: Graph,
    ring: FrameRing,
    /// Each frame's uniforms and set 0.
    scene_frames: PerFrame<SceneFrame>,
    /// Each frame's wind at the cluster corners and emitters (the wind field's part).
    forces: PerFrame<FrameForces>,
    /// The wind field (`render::wind`): the one `AnimationSettings::wind_field` names, or one
    /// given to `with_models`.
    wind: Box<dyn WindField>,
    /// Which of the library's fields `wind` is (`new`): a rebuild then builds the field its
    /// animation names; `None` for a field given to `with_models`, which stays.
    library_wind: Option<crate::wind::FieldKind>,
    /// Each frame's cull counts (the cull's part).
    cull_frames: PerFrame<CullFrame>,
    /// The camera the cull tests against when frozen (`None`: the view's camera).
    cull_camera: Option<Camera>,
    /// With `--msaa`: the multisampled images the scene passes draw into, made at the first
    /// frame's extent and remade when the extent or the sample count changes.
    multisampled: Option<MultisampleTarget>,
    /// The egui overlay's GPU state (`set_overlay`), shared with its passes; made on first use.
    overlay: Option<Rc<RefCell<OverlayGpu>>>,
    /// The simulation's fixed step (`FrameClock::dt`).
    time_step: f32,
    /// The pressed map (`render::animation::pressed`): trails and cuts, kept across rebuilds.
    pressed: Option<PressedMap>,
    /// The far field's placed draw and what it draws, when the graph has a far field
    /// (`Renderer::far_counts`).
    far: Option<crate::render::far_field::FarDraw>,
    /// The atlas of the far field last built: a rebuilt graph whose blades bake the same atlas
    /// draws from it with no bake (`far_field::passes`).
    far_atlas: std::rc::Weak<crate::render::far_field::atlas::Atlas>,
    /// The point the far field's band is measured from: the culling camera on a leash (world),
    /// kept across frames and rebuilds.
    band_eye: crate::render::far_rings::BandEye,
}

impl Renderer {
    /// Upload `scene` and build the passes and frames, with the CLI's models.
    pub fn new(
        device: Arc<Device>,
        scene: &Scene,
        settings: RenderSettings,
        animation: AnimationSettings,
    ) -> Result<Self> {
        let wind = crate::render::wind::build(animation.wind_field, &animation.fluid)?;
        let models = Models { wind, ..Models::default() };
        let mut renderer = Self::with_models(device, scene, settings, animation, models)?;
        renderer.library_wind = Some(renderer.animation.wind_field);
        Ok(renderer)
    }

    /// Upload `scene` and build the passes and frames, animated by `models` (a wind field and a
    /// blade response defined outside the library: `tests/new_model.rs`).
    pub fn with_models(
        device: Arc<Device>,
        scene: &Scene,
        settings: RenderSettings,
        animation: AnimationSettings,
        models: Models,
    ) -> Result<Self> {
        let settings = crate::render::settings::with_mode_rows(settings, &animation);
        let polygon = polygon_mode(&device, settings.wireframe)?;
        check_submission(&device, &settings)?;
        msaa::check(&device, &settings.msaa)?;
        if scene.field.is_some() {
            crate::render::settings::check_field(&settings)?;
        }
        let animation = for_device(&device, animation);
        let mut renderer = Self {
            device: device.clone(),
            settings,
            animation,
            scene: None,
            response: None,
            builders: Builders { response: models.response, classes: response::with_flowers(scene, models.classes)? },
            response_passes: Vec::new(),
            far: None,
            far_atlas: std::rc::Weak::new(),
            band_eye: Default::default(),
            poses: None,
            layouts: SceneLayouts::default(),
            graph: Graph::new(),
            ring: FrameRing::new(Vec::new()),
            scene_frames: PerFrame::default(),
            forces: PerFrame::default(),
            wind: models.wind,
            library_wind: None,
            cull_frames: PerFrame::default(),
            cull_camera: None,
            multisampled: None,
            overlay: None,
            time_step: DEFAULT_DT,
            pressed: None,
        };
        // The cull's buffers cover the blades' range, a block field's force corners the far
        // field's too.
        let reach = (settings.culling.blade_range(), settings.culling.wind_reach());
        let room = renderer.builders.classes.source_room();
        let scene_gpu = SceneGpu::upload(&device, scene, renderer.animation.cluster_size, reach, room)?;
        renderer.scene = Some(scene_gpu);
        renderer.layouts = scene_layouts(&device)?;
        renderer.pressed = Some(PressedMap::new(&device)?);
        renderer.build_frames()?;
        let scene_gpu = renderer.scene.as_ref().expect("uploaded");
        let path = (settings.culling.enabled, settings.floor);
        check_pose_records(&device, &renderer.animation, (scene_gpu.blade_count, settings.segments), path.0, path.1)?;
        let (response, poses) = renderer.build_response(&settings, &renderer.animation)?;
        renderer.response = Some(response);
        renderer.poses = Some(poses);
        renderer.build_graph(scene, polygon)?;
        Ok(renderer)
    }

    /// The frames in flight: the ring's part of each (commands, fence, queries) and each
    /// subsystem's (the forces, the cull counts, then the uniforms and set 0 that point at them).
    fn build_frames(&mut self) -> Result<()> {
        let (device, scene) = (&*self.device, self.scene.as_ref().expect("uploaded"));
        let (slots, statistics) = (self.settings.frames_in_flight, self.settings.pipeline_statistics);
        self.ring = FrameRing::new(PerFrame::new(device, slots, |i| Frame::new(device, i, statistics))?.into());
        let (corners, emitters) = (scene.wind_corner_count(), animation::collider_bins::EMITTER_BUFFER_ELEMENTS as u32);
        self.forces = PerFrame::new(device, slots, |i| FrameForces::new(device, i, corners, emitters))?;
        self.cull_frames = PerFrame::new(device, slots, |i| CullFrame::new(device, i))?;
        let forces = &self.forces;
        self.scene_frames = scene_frames(device, &mut self.layouts, scene, slots, |slot| frame_bindings(forces, slot))?;
        Ok(())
    }

    /// Rebuild the passes and the blade response for new `settings` and `animation`, keeping the
    /// scene on the GPU and the frames in flight (the viewer's live controls). The old passes and
    /// model are destroyed once the frames already submitted have finished — the frame ring's
    /// deletion queue, no queue idle. `scene` must be the one the renderer was built with.
    /// What the frames or the uploaded scene depend on (frames in flight, colour format,
    /// statistics, cluster size, a blade distance or far-field reach past the upload's,
    /// `fits_upload`) needs a new renderer: refused. On failure the renderer keeps
    /// its previous passes and model.
    pub fn rebuild(&mut self, scene: &Scene, settings: RenderSettings, animation: AnimationSettings) -> Result<()> {
        let settings = crate::render::settings::with_mode_rows(settings, &animation);
        let animation = for_device(&self.device, animation);
        let polygon = self.check_rebuild(scene, &settings, &animation)?;
        let device = self.device.clone();
        // The same animation at the same segment count keeps its response (and its state): only
        // the passes are rebuilt, with no upload. (With the cull or without it, the pose records
        // have room for placed levels or none.)
        let keep_response = animation == self.animation
            && settings.segments == self.settings.segments
            && settings.culling.enabled == self.settings.culling.enabled;
        let blades = self.scene_gpu().blade_count;
        check_pose_records(&device, &animation, (blades, settings.segments), settings.culling.enabled, settings.floor)?;
        let new_wind = match self.library_wind.is_some_and(|k| k != animation.wind_field) {
            true => Some(crate::render::wind::build(animation.wind_field, &animation.fluid)?),
            false => None,
        };
        let built = match keep_response {
            true => None,
            false => Some(self.build_response(&settings, &animation)?),
        };
        let mut previous = (
            std::mem::replace(&mut self.settings, settings),
            std::mem::replace(&mut self.animation, animation),
            built.map(|(response, poses)| self.swap_response(Some((response, poses)))),
            (std::mem::take(&mut self.graph), (self.far, self.far_atlas.clone())),
        );
        // The scene's resources keep their states; a replaced response's and pose records' go
        // with them.
        let mut states = previous.3 .0.states().clone();
        if let Some((old_response, old_poses)) = &previous.2 {
            for (resource, _) in old_response.iter().flat_map(|r| r.tracked()) {
                states.forget(resource);
            }
            for buffer in old_poses.iter().flat_map(|p| p.buffers()) {
                states.forget(Resource::Buffer(buffer));
            }
        }
        self.graph.set_states(states);
        // The passes added from outside, the temporal pairs and the clock carry over.
        let kept = previous.3 .0.keep();
        self.graph.adopt(kept);
        // The library's field follows the animation's `wind_field` (its passes go with the old
        // graph; the field itself holds no GPU object).
        let kind = self.animation.wind_field;
        let old_wind = new_wind.map(|wind| (std::mem::replace(&mut self.wind, wind), self.library_wind.replace(kind)));
        let built = self.build_graph(scene, polygon);
        // Pre-recorded command buffers name the old pipelines: record again.
        self.ring.forget_replays();
        let (old_settings, old_animation, old_response, (old_graph, old_far)) = previous;
        let (retired_response, retired_graph) = match built {
            Ok(()) => (old_response, old_graph),
            Err(e) => {
                // Back to the previous passes and response; the half-built ones are retired.
                (self.settings, (self.far, self.far_atlas)) = (old_settings, old_far);
                self.animation = old_animation;
                if let Some((wind, kind)) = old_wind {
                    (self.wind, self.library_wind) = (wind, kind);
                }
                let new_response = old_response.map(|(response, poses)| self.swap_response(response.zip(poses)));
                let mut new_graph = std::mem::replace(&mut self.graph, old_graph);
                let kept = new_graph.keep();
                self.graph.adopt(kept);
                self.retire(new_response, new_graph);
                return Err(e);
            }
        };
        self.retire(retired_response, retired_graph);
        Ok(())
    }

    /// Destroy a response, its pose records and a graph's passes once the frames submitted so
    /// far have finished.
    fn retire(&mut self, response: Option<RetiredResponse>, graph: Graph) {
        self.ring.defer(
            &self.device,
            Box::new(move |device| {
                // SAFETY: the frames that used them have finished (the deletion queue's rule).
                unsafe {
                    graph.destroy(device);
                    if let Some((response, poses)) = response {
                        if let Some(response) = response {
                            response.destroy(device);
                        }
                        if let Some(poses) = poses {
                            poses.destroy(device);
                        }
                    }
                }
            }),
        );
    }

    fn scene_gpu(&self) -> &SceneGpu {
        self.scene.as_ref().expect("scene uploaded in new")
    }

    /// Place a raw timestamp of the queue, read before the frames, on their timeline (their
    /// `FrameTimings` nanoseconds, which keep counting when the counter wraps); in nanoseconds.
    pub fn place_timestamp(&mut self, raw: u64, period_ns: f64) -> f64 {
        self.ring.place_timestamp(raw, period_ns)
    }

    /// Wait until the next frame slot is free (its fence signalled) and return the slot with
    /// the timings of the frame it rendered last, if any. Only that slot's fence is waited: the
    /// other frames in flight keep running.
    pub fn begin_frame(&mut self) -> Result<(usize, Option<FrameTimings>)> {
        let (slot, timings) = self.ring.begin(&self.device)?;
        Ok((slot, timings.map(|t| self.with_counts(slot, t))))
    }

    /// `timings` of `slot`'s last frame with what the subsystems' parts of it counted (the cull).
    fn with_counts(&self, slot: usize, timings: FrameTimings) -> FrameTimings {
        FrameTimings { cull: self.cull_frames[slot].counts(), ..timings }
    }

    /// The semaphore a swapchain image for `slot` is acquired with.
    pub fn acquire_semaphore(&self, slot: usize) -> vk::Semaphore {
        self.ring.frame(slot).acquire
    }

    /// Destroy `deletion` once every frame submitted so far has finished (a rebuilt pipeline, a
    /// replaced buffer), without waiting for the queue.
    pub fn defer(&mut self, deletion: Deletion) {
        self.ring.defer(&self.device, deletion);
    }

    /// Wait for every frame and the queue, and run every deferred deletion (see `FrameRing::drain`).
    pub fn drain_deletions(&mut self) -> Result<()> {
        self.ring.drain(&self.device)
    }

    /// Forget `resource` in the graph (destroyed: its handle may be reused by a new object).
    pub fn forget(&mut self, resource: Resource) {
        self.graph.forget(resource);
    }

    /// Drop every kept recording (`Prerecorded`): they name objects that are being replaced.
    pub fn forget_recordings(&mut self) {
        self.ring.forget_replays();
    }

    /// Destroy `deletion` once `frames` more frames have completed (what the presentation engine
    /// may still hold: an old swapchain, its views and present semaphores).
    pub fn defer_frames(&mut self, frames: u64, deletion: Deletion) {
        self.ring.defer_frames(frames, deletion);
    }

    /// Deletions queued behind frames in flight (see `defer`).
    pub fn pending_deletions(&self) -> usize {
        self.ring.pending_deletions()
    }

    /// Make the `nth` next submission fail as if the driver had lost the device (tests).
    pub fn inject_submit_failure(&mut self, nth: u64) {
        self.ring.inject_submit_failure(nth);
    }

    /// Record and submit the frame of `slot` (after `begin_frame`) into `target`: uniforms and
    /// corner forces written, passes recorded with their barriers, then `outputs` (a copy to the
    /// host, presentation), and the submission waits and signals `sync`'s semaphores (a
    /// swapchain's acquire and present) and the slot's fence.
    pub fn submit_frame(
        &mut self,
        slot: usize,
        target: &TargetView,
        camera: &Camera,
        time: f32,
        sync: FrameSync,
        outputs: Outputs,
    ) -> Result<()> {
        // A block field's cells are indexed in 32 bits (the CLI refuses such cameras first).
        self.scene_gpu().field.as_ref().map_or(Ok(()), |_| check_camera(camera.position)).map_err(Error::bad_input)?;
        let uniforms = self.prepare_frame(slot, target, camera, time)?;
        // The resource states move on only if the frame is submitted: a frame that failed to
        // record or submit never runs, and the next frame's barriers must not assume it did.
        let entry = self.graph.states().clone();
        let submitted = self
            .record_frame(slot, target, record::FrameIn { uniforms: &uniforms, time }, outputs)
            .and_then(|started| self.ring.submit(&self.device, slot, sync, started));
        match submitted {
            Ok(()) => self.graph.frame_submitted(),
            Err(_) => {
                self.graph.set_states(entry);
                self.graph.frame_dropped();
            }
        }
        self.overlay_submitted(submitted.is_ok());
        submitted
    }

    /// Write the uniforms, forces and overlay of `slot`'s frame; returns the uniforms.
    fn prepare_frame(&mut self, slot: usize, target: &TargetView, camera: &Camera, time: f32) -> Result<FrameUniforms> {
        let eye = self.cull_camera.as_ref().unwrap_or(camera).position.as_dvec3();
        self.band_eye.follow(eye, f64::from(self.band_leash()));
        let uniforms = self.frame_uniforms(camera, time, target.extent);
        self.scene_frames[slot].uniforms.write(0, &[uniforms]);
        self.update_wind(slot, camera, time);
        let clock = self.animation.clock;
        let step = ResponseStep {
            step: clock.steps_to(f64::from(time)),
            dt: clock.dt as f32,
            frame: self.graph.frames_submitted(),
            slot,
            time: f64::from(time),
            origin: self.origin_of(camera),
        };
        self.response.as_deref_mut().expect("built").step(&step);
        self.prepare_overlay(slot, target.extent)?;
        Ok(uniforms)
    }

    /// Wait for every frame in flight (before reading a screenshot; never inside a frame).
    pub fn wait_all_frames(&mut self) -> Result<()> {
        self.ring.wait_all(&self.device).map(|_| ())
    }
}

/// `animation` as `device` can run it: a keyframe texture whose format the device cannot sample
/// falls back to one it can (`keyframe_gpu::sampled_encoding`; `Renderer::animation` tells).
fn for_device(device: &Device, mut animation: AnimationSettings) -> AnimationSettings {
    animation.encoding = crate::render::animation::keyframe_gpu::sampled_encoding(device, animation.encoding);
    animation
}

impl Drop for Renderer {
    fn drop(&mut self) {
        // Teardown, not a frame: waiting for the whole device is the point.
        let _ = self.device.wait_idle();
        let device = &*self.device;
        // SAFETY: the device is idle.
        unsafe {
            std::mem::take(&mut self.graph).destroy(device);
            std::mem::replace(&mut self.ring, FrameRing::new(Vec::new())).destroy(device);
            std::mem::take(&mut self.scene_frames).destroy(device);
            std::mem::take(&mut self.forces).destroy(device);
            std::mem::take(&mut self.cull_frames).destroy(device);
            if let Some(pressed) = self.pressed.take() {
                pressed.destroy(device);
            }
            if let Some(response) = self.response.take() {
                response.destroy(device);
            }
            if let Some(poses) = self.poses.take() {
                poses.destroy(device);
            }
            SceneLayouts::destroy(&self.layouts, device);
            if let Some(multisampled) = self.multisampled.take() {
                multisampled.destroy(device);
            }
            if let Some(scene) = self.scene.take() {
                scene.destroy(device);
            }
        }
        // SAFETY: the device is idle.
        unsafe { self.destroy_overlay() };
    }
}
