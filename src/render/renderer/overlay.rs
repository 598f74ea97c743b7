//! The renderer's egui overlay (`render::overlay`): what the viewer hands it each frame, its GPU
//! state made on first use and kept across rebuilds, the frame's part prepared before the passes
//! are recorded, and what a submitted frame frees.

use std::cell::RefCell;
use std::rc::Rc;

use ash::vk;

use super::Renderer;
use crate::error::Result;
use crate::render::overlay::{OverlayFrame, OverlayGpu, Texture, TextureChanges};
use crate::render::passes::overlay::{OverlayPass, OverlayUploadPass};
use crate::vk::{Access, Buffer, Device, Resource};

impl Renderer {
    /// Draw `frame` over the next submitted frame, as the graph's last passes. `None`: no overlay
    /// (the passes are skipped, `declare` returns None). Texture `set`s of the delta are applied
    /// before the draw in the same frame; `free`s after the frames in flight that may still
    /// sample them.
    ///
    /// The primitives are drawn again by every later frame until the next call (the viewer need
    /// not run egui for frames where nothing changed). The textures are kept while hidden. A
    /// frame that fails the checks (`Error::BadInput`: a mesh of an unknown texture, an index past
    /// its vertices, a region outside its texture, a paint callback…) changes nothing.
    pub fn set_overlay(&mut self, frame: Option<OverlayFrame>) -> Result<()> {
        let Some(frame) = frame else {
            if let Some(overlay) = self.overlay.as_ref().filter(|o| o.borrow().is_shown()) {
                overlay.borrow_mut().hide();
                // A kept recording (`Prerecorded`) holds the overlay's draws: record again.
                self.ring.forget_replays();
            }
            return Ok(());
        };
        self.ring.forget_replays();
        let overlay = match &self.overlay {
            Some(overlay) => overlay.clone(),
            None => self.create_overlay()?,
        };
        let mut changes = TextureChanges::default();
        let shown = overlay.borrow_mut().show(&self.device, frame, &mut changes);
        for image in changes.created {
            self.graph.import(Resource::color(image), &[Access::Nothing]);
        }
        self.retire_textures(changes.retired);
        shown
    }

    /// The overlay's state for the renderer's output format, and its passes at the end of the
    /// graph (`build_graph` adds them to every later graph).
    fn create_overlay(&mut self) -> Result<Rc<RefCell<OverlayGpu>>> {
        let settings = &self.settings;
        // An *_SRGB target encodes what the shader writes; a UNORM one takes it as it is.
        let linear_target = !settings.encode_srgb;
        let gpu = OverlayGpu::new(&self.device, settings.color_format, linear_target, self.ring.slots())?;
        let overlay = Rc::new(RefCell::new(gpu));
        self.overlay = Some(overlay.clone());
        self.add_overlay_passes();
        self.ring.forget_replays();
        Ok(overlay)
    }

    /// Append the overlay's passes to the graph, if there is an overlay.
    pub(super) fn add_overlay_passes(&mut self) {
        if let Some(overlay) = &self.overlay {
            self.graph.add(OverlayUploadPass::new(overlay.clone()));
            self.graph.add(OverlayPass::new(overlay.clone()));
        }
    }

    /// The overlay's part of frame `slot` into a target of `extent` (after its fence): buffers
    /// written, draws and copies listed. A frame that draws it is never replayed.
    pub(super) fn prepare_overlay(&mut self, slot: usize, extent: vk::Extent2D) -> Result<()> {
        let Some(overlay) = self.overlay.clone() else { return Ok(()) };
        let mut retired = Vec::new();
        let mut overlay = overlay.borrow_mut();
        let prepared = overlay.prepare(&self.device, slot, extent, &mut retired);
        if overlay.is_shown() {
            self.ring.forget_replays();
        }
        self.retire_buffers(retired);
        prepared
    }

    /// After a frame's submission (`submitted`: it was): its copies done, the textures freed
    /// since retired behind it.
    pub(super) fn overlay_submitted(&mut self, submitted: bool) {
        let Some(overlay) = self.overlay.clone() else { return };
        let freed = overlay.borrow_mut().submitted(submitted);
        self.retire_textures(freed);
    }

    /// Forget `textures` in the graph and destroy them once the frames submitted so far finish.
    fn retire_textures(&mut self, textures: Vec<Texture>) {
        if textures.is_empty() {
            return;
        }
        for texture in &textures {
            self.graph.forget(Resource::color(texture.image.raw));
        }
        self.defer(Box::new(move |device: &Device| {
            for texture in textures {
                // SAFETY: the frames that sampled it have finished (the deletion queue's rule).
                unsafe { texture.destroy(device) };
            }
        }));
    }

    /// Destroy `buffers` once the frames submitted so far finish.
    fn retire_buffers(&mut self, buffers: Vec<Buffer>) {
        if buffers.is_empty() {
            return;
        }
        self.defer(Box::new(move |device: &Device| {
            for buffer in buffers {
                // SAFETY: the frames that read it have finished (the deletion queue's rule).
                unsafe { buffer.destroy(device) };
            }
        }));
    }

    /// Destroy the overlay's state (teardown).
    ///
    /// # Safety
    /// The device must be idle.
    pub(super) unsafe fn destroy_overlay(&mut self) {
        if let Some(overlay) = self.overlay.take() {
            // SAFETY: per the contract. The graphs' passes hold the state too, but no longer
            // record: it is emptied here whoever holds it.
            unsafe { overlay.borrow_mut().destroy(&self.device) };
        }
    }
}
