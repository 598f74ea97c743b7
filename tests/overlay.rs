//! The egui overlay's passes (`render::overlay`) on lavapipe with validation and synchronization
//! validation: an egui window drawn over an offscreen render changes the pixels inside its
//! rectangle and none outside; the font sent once keeps drawing the text on later frames and
//! across a rebuild (to `--msaa 4`, where the overlay draws on the resolved target); new glyphs
//! update a region of the font; a second texture is sampled nearest, then freed and destroyed
//! after its last frame; hiding the overlay gives the scene back bit for bit; the passes are
//! timed; nothing leaks. The pictures are written to `target/tmp/overlay/`.

mod support;

use std::sync::Arc;

use ash::vk;
use meadow::app::{with_device, write_png, GpuOptions};
use meadow::render::culling::Culling;
use meadow::render::msaa::Msaa;
use meadow::render::overlay::OverlayFrame;
use meadow::render::{FrameTimings, OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::{Camera, Scene};
use meadow::vk::{live, Device, DeviceSelector};

const EXTENT: vk::Extent2D = vk::Extent2D { width: 360, height: 240 };
/// Not 1: the scissors and the screen size go through the scale.
const PIXELS_PER_POINT: f32 = 1.5;

/// An egui context showing one window with a label and a button at a known position.
struct Ui {
    ctx: egui::Context,
}

impl Ui {
    fn new() -> Self {
        let ctx = egui::Context::default();
        ctx.set_pixels_per_point(PIXELS_PER_POINT);
        // No shadow: the window's rectangle is all it paints.
        ctx.style_mut(|style| {
            style.visuals.window_shadow = egui::Shadow::NONE;
            style.visuals.popup_shadow = egui::Shadow::NONE;
        });
        Self { ctx }
    }

    /// One egui frame: its output and the window's rectangle in points.
    fn run(&self) -> (egui::FullOutput, egui::Rect) {
        let (output, window, _) = self.run_with(None);
        (output, window)
    }

    /// One egui frame, with `image` under the button (and a label with glyphs not drawn before)
    /// when given: its output, the window's and the image's rectangles in points.
    fn run_with(&self, image: Option<egui::TextureId>) -> (egui::FullOutput, egui::Rect, egui::Rect) {
        let size = egui::vec2(EXTENT.width as f32, EXTENT.height as f32) / PIXELS_PER_POINT;
        let screen_rect = Some(egui::Rect::from_min_size(egui::Pos2::ZERO, size));
        let input = egui::RawInput { screen_rect, ..Default::default() };
        let (mut window, mut shown_image) = (egui::Rect::NOTHING, egui::Rect::NOTHING);
        let output = self.ctx.run(input, |ctx| {
            let panel = egui::Window::new("meadow").fixed_pos([16.0, 12.0]).resizable(false).collapsible(false);
            let shown = panel.fade_in(false).show(ctx, |ui| {
                ui.label("Overlay: 42 blades");
                let _ = ui.button("Capture");
                if let Some(id) = image {
                    ui.label("Wind: 7 m/s ✔ ¼");
                    shown_image = ui.image((id, egui::vec2(24.0, 24.0))).rect;
                }
            });
            window = shown.expect("the window is open").response.rect;
        });
        (output, window, shown_image)
    }

    fn frame(&self, output: egui::FullOutput, textures: egui::TexturesDelta) -> OverlayFrame {
        let primitives = self.ctx.tessellate(output.shapes, output.pixels_per_point);
        OverlayFrame { primitives, textures, pixels_per_point: output.pixels_per_point }
    }
}

/// A picture and how long its overlay passes took.
struct Render {
    rgba: Vec<u8>,
    timings: FrameTimings,
}

impl Render {
    fn pixel(&self, x: u32, y: u32) -> &[u8] {
        let i = 4 * (y * EXTENT.width + x) as usize;
        &self.rgba[i..i + 4]
    }

    fn pass_ms(&self, name: &str) -> Option<f64> {
        self.timings.passes.iter().find(|p| p.name == name).map(|p| p.ms)
    }
}

/// A rectangle of pixels: `[x0, y0, x1, y1)`.
type Pixels = [u32; 4];

/// `rect` (points) in pixels, grown by `margin` pixels (shrunk when negative).
fn pixels(rect: egui::Rect, margin: f32) -> Pixels {
    let r = rect.expand(margin / PIXELS_PER_POINT);
    let px = |v: f32, limit: u32| ((v * PIXELS_PER_POINT).round().max(0.0) as u32).min(limit);
    [px(r.min.x, EXTENT.width), px(r.min.y, EXTENT.height), px(r.max.x, EXTENT.width), px(r.max.y, EXTENT.height)]
}

fn inside([x0, y0, x1, y1]: Pixels, x: u32, y: u32) -> bool {
    (x0..x1).contains(&x) && (y0..y1).contains(&y)
}

fn all_pixels() -> impl Iterator<Item = (u32, u32)> {
    (0..EXTENT.height).flat_map(|y| (0..EXTENT.width).map(move |x| (x, y)))
}

/// Pixels outside `panel` (grown by 2 px for the frame's stroke) that differ, and the share of
/// pixels inside it (shrunk by 3 px for the rounded corners) that differ.
fn compare(scene: &Render, overlay: &Render, panel: egui::Rect) -> (usize, f64) {
    let (outer, inner) = (pixels(panel, 2.0), pixels(panel, -3.0));
    let outside = all_pixels().filter(|&(x, y)| !inside(outer, x, y) && scene.pixel(x, y) != overlay.pixel(x, y));
    let within: Vec<_> = all_pixels().filter(|&(x, y)| inside(inner, x, y)).collect();
    let changed = within.iter().filter(|&&(x, y)| scene.pixel(x, y) != overlay.pixel(x, y)).count();
    (outside.count(), changed as f64 / within.len().max(1) as f64)
}

/// The pixels inside `panel` (shrunk by 3 px) of two renders are the same: the same text on the
/// same opaque panel, whatever the scene under it.
fn same_panel(a: &Render, b: &Render, panel: egui::Rect) -> bool {
    let inner = pixels(panel, -3.0);
    all_pixels().filter(|&(x, y)| inside(inner, x, y)).all(|(x, y)| a.pixel(x, y)[..3] == b.pixel(x, y)[..3])
}

/// Pixels inside `panel` brighter than its fill: the text and the button.
fn text_pixels(render: &Render, panel: egui::Rect) -> usize {
    let inner = pixels(panel, -3.0);
    let fill = render.pixel(inner[0] + 1, inner[3] - 2)[0];
    all_pixels().filter(|&(x, y)| inside(inner, x, y) && render.pixel(x, y)[0] > fill.saturating_add(40)).count()
}

/// The scene and its renderer.
struct Bench {
    scene: Scene,
    camera: Camera,
    renderer: Renderer,
    target: OffscreenTarget,
}

impl Bench {
    fn render(&mut self) -> meadow::Result<Render> {
        let timings = self.renderer.render_offscreen(&mut self.target, &self.camera, 0.0)?;
        Ok(Render { rgba: self.target.pixels().to_vec(), timings })
    }
}

fn settings(msaa: u32) -> RenderSettings {
    let mut settings = RenderSettings { frames_in_flight: 2, ..RenderSettings::offscreen(4, Culling::default_for(4)) };
    settings.msaa = Msaa { samples: msaa, ..Msaa::default() };
    settings
}

fn save(render: &Render, name: &str) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("overlay");
    std::fs::create_dir_all(&dir).expect("scratch directory");
    write_png(&dir.join(name), (EXTENT.width, EXTENT.height), &render.rgba).expect("png written");
}

/// Two egui frames before the first drawn one (a new window is laid out invisibly first), their
/// texture deltas merged: the font atlas and the glyphs added to it.
fn first_frame(ui: &Ui) -> (OverlayFrame, egui::Rect) {
    let mut textures = egui::TexturesDelta::default();
    let mut last = None;
    for _ in 0..3 {
        let (mut output, rect) = ui.run();
        textures.append(std::mem::take(&mut output.textures_delta));
        last = Some((output, rect));
    }
    let (output, rect) = last.expect("ran");
    assert!(!textures.set.is_empty(), "egui sent its font");
    (ui.frame(output, textures), rect)
}

/// A later egui frame: no texture delta (egui sends the font once).
fn later_frame(ui: &Ui, panel: egui::Rect) -> OverlayFrame {
    let (mut output, rect) = ui.run();
    assert_eq!(rect, panel, "the window stays put");
    let textures = std::mem::take(&mut output.textures_delta);
    assert!(textures.is_empty(), "no texture delta after the first frames: {textures:?}");
    ui.frame(output, textures)
}

fn exercise(device: &Arc<Device>) -> meadow::Result<()> {
    let scene = Scene::generate(2000, 1);
    let camera = Camera::default_for(&scene.terrain);
    let renderer = Renderer::new(device.clone(), &scene, settings(1), Default::default())?;
    let target = OffscreenTarget::new(device, EXTENT)?;
    let mut bench = Bench { scene, camera, renderer, target };
    let result = overlay_frames(&mut bench);
    drop(bench.renderer);
    // SAFETY: the renderer waited for the device on drop.
    unsafe { bench.target.destroy(device) };
    result
}

fn overlay_frames(bench: &mut Bench) -> meadow::Result<()> {
    let ui = Ui::new();
    let scene = bench.render()?;
    assert_eq!(scene.rgba, bench.render()?.rgba, "the scene renders the same twice");
    let (frame, panel) = first_frame(&ui);
    bench.renderer.set_overlay(Some(frame))?;
    let first = bench.render()?;
    save(&first, "overlay.png");
    let (outside, inside) = compare(&scene, &first, panel);
    assert_eq!(outside, 0, "pixels changed outside the panel {panel:?}");
    assert!(inside > 0.95, "{:.1} % of the panel {panel:?} changed", 100.0 * inside);
    let upload = first.pass_ms("overlay upload").expect("the font is uploaded by the first frame");
    let draw = first.pass_ms("overlay").expect("an overlay pass");
    assert!(upload > 0.0 && draw > 0.0, "timed: upload {upload} ms, overlay {draw} ms");
    let text = text_pixels(&first, panel);
    assert!(text > 100, "{text} text pixels");

    bench.renderer.set_overlay(Some(later_frame(&ui, panel)))?;
    let second = bench.render()?;
    assert_eq!(second.rgba, first.rgba, "the second frame draws the same text with the kept font");
    assert_eq!(second.pass_ms("overlay upload"), None, "nothing to upload");
    assert!(second.pass_ms("overlay").is_some_and(|ms| ms > 0.0));

    bench.renderer.set_overlay(None)?;
    let hidden = bench.render()?;
    assert!(hidden.rgba == scene.rgba, "hidden: the scene bit for bit");
    assert_eq!(hidden.pass_ms("overlay"), None);

    bench.renderer.rebuild(&bench.scene, settings(4), Default::default())?;
    let msaa_scene = bench.render()?;
    bench.renderer.set_overlay(Some(later_frame(&ui, panel)))?;
    let msaa = bench.render()?;
    save(&msaa, "overlay-msaa4.png");
    let (outside, inside) = compare(&msaa_scene, &msaa, panel);
    assert!(outside == 0 && inside > 0.95, "msaa: {outside} outside, {:.1} % inside", 100.0 * inside);
    assert!(same_panel(&first, &msaa, panel), "the panel is drawn the same after the rebuild");
    let names = bench.renderer.pass_names();
    assert_eq!(names[names.len() - 3..], ["resolve", "overlay upload", "overlay"], "last passes: {names:?}");
    println!(
        "overlay pass at {}x{}: {:.3} ms (msaa: {:.3} ms)",
        EXTENT.width,
        EXTENT.height,
        draw,
        msaa.pass_ms("overlay").unwrap_or(0.0)
    );

    textures_come_and_go(bench, &ui, &msaa_scene)?;
    bench.renderer.set_overlay(None)?;
    assert!(bench.render()?.rgba == msaa_scene.rgba, "hidden after the rebuild: the scene bit for bit");
    Ok(())
}

/// Live images (`vk::live`; this file's only test makes them).
fn live_images() -> i64 {
    live::by_type().into_iter().find(|(kind, _)| kind == "IMAGE").map_or(0, |(_, n)| n)
}

/// A second texture, sampled nearest, shown then freed (destroyed once its frame is done), and
/// glyphs added to the font by a region update.
fn textures_come_and_go(bench: &mut Bench, ui: &Ui, scene: &Render) -> meadow::Result<()> {
    let images = live_images();
    let [red, blue] = [egui::Color32::from_rgb(255, 0, 0), egui::Color32::from_rgb(0, 0, 255)];
    let checker = egui::ColorImage::new([2, 2], vec![red, blue, blue, red]);
    let handle = ui.ctx.load_texture("checker", checker, egui::TextureOptions::NEAREST);
    let (mut output, panel, image) = ui.run_with(Some(handle.id()));
    let textures = std::mem::take(&mut output.textures_delta);
    let sets: Vec<_> = textures.set.iter().map(|(id, delta)| (*id, delta.pos)).collect();
    assert!(sets.contains(&(handle.id(), None)), "the checker is set whole: {sets:?}");
    let font = egui::TextureId::default();
    assert!(sets.iter().any(|&(id, pos)| id == font && pos.is_some()), "new glyphs update a region: {sets:?}");
    bench.renderer.set_overlay(Some(ui.frame(output, textures)))?;
    let shown = bench.render()?;
    save(&shown, "overlay-image.png");
    assert_eq!(live_images(), images + 1, "the checker's image");
    let (outside, inside) = compare(scene, &shown, panel);
    assert!(outside == 0 && inside > 0.95, "image: {outside} outside, {:.1} % inside", 100.0 * inside);
    // Nearest: each texel's quarter of the image is its colour exactly (white tint, opaque).
    let quarter = |qx: f32, qy: f32| {
        let at = image.min + image.size() * egui::vec2(0.25 + 0.5 * qx, 0.25 + 0.5 * qy);
        let [x, y] = [at.x, at.y].map(|v| (v * PIXELS_PER_POINT) as u32);
        shown.pixel(x, y)[..3].to_vec()
    };
    assert_eq!([quarter(0.0, 0.0), quarter(1.0, 0.0)], [vec![255, 0, 0], vec![0, 0, 255]]);
    assert_eq!([quarter(0.0, 1.0), quarter(1.0, 1.0)], [vec![0, 0, 255], vec![255, 0, 0]]);

    drop(handle);
    let (mut output, panel, _) = ui.run_with(None);
    let textures = std::mem::take(&mut output.textures_delta);
    assert_eq!(textures.free.len(), 1, "the checker is freed: {textures:?}");
    bench.renderer.set_overlay(Some(ui.frame(output, textures)))?;
    let after = bench.render()?;
    let (outside, inside) = compare(scene, &after, panel);
    assert!(outside == 0 && inside > 0.95, "freed: {outside} outside, {:.1} % inside", 100.0 * inside);
    assert_eq!(live_images(), images, "the checker's image is destroyed after its last frame");
    Ok(())
}

#[test]
fn the_overlay_draws_inside_its_panel_only_and_keeps_its_textures() {
    let before = live::total();
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, exercise);
    result.expect("overlay frames");
    assert_eq!(messages, Some(0), "validation messages");
    assert_eq!(live::total(), before, "left alive: {:?}", live::by_type());
}
