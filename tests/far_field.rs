//! The far field (issue #37, `render::far_field`), on lavapipe with validation and
//! synchronization validation: from the landscape camera it draws plants past 1 km and changes
//! the picture there against `--far-field off`, the same on every run and thread count, and out
//! to 10 km clean; under opposite winds its plants shift the way the blades do, and round a
//! source and round a collider they lean away as the blades do; a covering map of 0 grows none;
//! its atlas is baked once, and every level of it keeps level 0's mean coverage; blended, it is
//! placed far to near in the CPU's order of its keys; bad input is refused in one line.

mod support;

use std::sync::Arc;

use ash::vk;
use meadow::app::{with_device, GpuOptions};
use meadow::render::animation::{AnimationSettings, Mode};
use meadow::render::culling::Culling;
use meadow::render::{OffscreenTarget, RenderSettings, Renderer};
use meadow::scene::camera::{rows_below_horizon, FOV_Y_DEG, LANDSCAPE_HEIGHT, LANDSCAPE_PITCH_DEG};
use meadow::scene::field::FieldSpec;
use meadow::scene::{CameraChoice, Scene};
use meadow::vk::DeviceSelector;
use support::{scratch, Picture};

const ROWS: u32 = 720;

/// The landscape camera over an unbounded field under a light fog (at 2 km a surface keeps two
/// thirds of its colour), static blades, the ground to 2.5 km.
const LANDSCAPE: &[&str] =
    &["--field", "infinite", "--camera", "landscape", "--mode", "static", "--fog", "0.0002", "--view-distance", "2500"];

/// The landscape at 1280 × 720.
const FULL: &[&str] = &["--size", "1280x720"];

/// A camera 1.5 m up looking at the ground to 60 m, under a light fog and no gusts, small: the
/// lean tests' view of far plants from 5 m (blades to 6 m) or of blades to 60 m.
const CLOSE: &[&str] = &[
    "--field",
    "infinite",
    "--view-distance",
    "60",
    "--camera",
    "0,1.5,0,0,-12",
    "--fog",
    "0.001",
    "--no-gusts",
    "--size",
    "320x180",
];

/// `meadow render --validation` of `args` (and `env`): its standard output and picture.
fn render(name: &str, args: &[&str], env: &[(&str, &str)]) -> (String, Picture) {
    let out = scratch(&format!("far-field-{name}")).join("out.png");
    let output = support::meadow()
        .envs(env.iter().copied())
        .args(["render", "--validation", "--device", support::DEVICE])
        .args(args)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("run meadow");
    support::assert_clean(&output);
    (String::from_utf8_lossy(&output.stdout).to_string(), Picture::load(&out))
}

/// The row where flat ground `distance` metres ahead lies from the landscape camera.
fn row_at(distance: f32) -> f32 {
    let focal = 0.5 * ROWS as f32 / (0.5 * FOV_Y_DEG.to_radians()).tan();
    let horizon = 0.5 * ROWS as f32 - focal * (-LANDSCAPE_PITCH_DEG).to_radians().tan();
    horizon + rows_below_horizon(LANDSCAPE_HEIGHT, LANDSCAPE_PITCH_DEG, distance, ROWS)
}

/// The far field's line of `render`: its plant count.
fn far_plants(stdout: &str) -> u32 {
    let line =
        stdout.lines().find(|l| l.starts_with("far field: ")).unwrap_or_else(|| panic!("no far field line:\n{stdout}"));
    line["far field: ".len()..].split(' ').next().and_then(|n| n.parse().ok()).expect("a count")
}

/// The share of the blocks 8 pixels wide across `rows` whose mean colour differs between `a`
/// and `b` by more than one level.
fn differing_blocks(a: &Picture, b: &Picture, rows: std::ops::RangeInclusive<u32>) -> f64 {
    differing_blocks_in(a, b, rows, 0..a.width / 8)
}

/// `differing_blocks` over the blocks `blocks` (8 pixels wide, from the left) alone.
fn differing_blocks_in(
    a: &Picture,
    b: &Picture,
    rows: std::ops::RangeInclusive<u32>,
    blocks: std::ops::Range<u32>,
) -> f64 {
    let count = blocks.len() as u32;
    let differing = blocks
        .filter(|&block| {
            let mean = |p: &Picture| -> [f64; 3] {
                let mut sum = [0.0; 3];
                for y in rows.clone() {
                    for x in block * 8..block * 8 + 8 {
                        let px = p.pixel(x, y);
                        (0..3).for_each(|c| sum[c] += f64::from(px[c]));
                    }
                }
                let n = f64::from(8 * rows.clone().count() as u32);
                sum.map(|s| s / n)
            };
            let (ma, mb) = (mean(a), mean(b));
            (0..3).any(|c| (ma[c] - mb[c]).abs() > 1.0)
        })
        .count();
    differing as f64 / f64::from(count)
}

#[test]
fn past_1_km_the_far_field_draws_plants_the_same_on_every_run_and_thread_count() {
    let landscape = [LANDSCAPE, FULL].concat();
    let (stdout, far) = render("far", &landscape, &[("LP_NUM_THREADS", "4")]);
    let (_, off) = render("off", &[&landscape, ["--far-field", "off"].as_slice()].concat(), &[]);
    let plants = far_plants(&stdout);
    assert!(plants > 100, "{stdout}");
    // Between 1 and 2 km ahead: a row under the 2 km line to a row over the 1 km one.
    let rows = row_at(2000.0).ceil() as u32..=row_at(1000.0).floor() as u32;
    assert!(rows.clone().count() >= 4, "{rows:?}");
    let share = differing_blocks(&far, &off, rows.clone());
    assert!(share >= 0.5, "only {:.0} % of the blocks between 1 and 2 km differ from --far-field off", 100.0 * share);
    // Nothing of the far field nearer than its band: the rows under 100 m are the same.
    let near = row_at(100.0).ceil() as u32..=ROWS - 1;
    assert_eq!(differing_blocks(&far, &off, near), 0.0);
    // The same picture on one thread and on a second run.
    let (again, one) = render("one-thread", &landscape, &[("LP_NUM_THREADS", "1")]);
    assert_eq!(one.rgb, far.rgb, "the far field differs between LP_NUM_THREADS 4 and 1");
    assert_eq!(far_plants(&again), plants);
    // Blended (`--fade blend`: the ordered placement, blending in primitive order), small: the
    // same on 1 and 4 threads, and not the dither's picture.
    let small = [LANDSCAPE, &["--size", "320x180", "--fade", "blend"]].concat();
    let (_, blend_four) = render("blend-four", &small, &[("LP_NUM_THREADS", "4")]);
    let (_, blend_one) = render("blend-one", &small, &[("LP_NUM_THREADS", "1")]);
    assert_eq!(blend_one.rgb, blend_four.rgb, "the blended far field differs between LP_NUM_THREADS 4 and 1");
    let (_, dither) = render("dither-small", &[LANDSCAPE, &["--size", "320x180"]].concat(), &[]);
    assert_ne!(dither.rgb, blend_four.rgb, "--fade blend drew the dither's picture");
}

#[test]
fn the_far_field_reaches_10_km_clean_with_either_mesh() {
    let wide = &["--field", "infinite", "--camera", "landscape", "--fog", "0.0002", "--size", "320x180"];
    for (mesh, fade) in [("billboards", "dither"), ("stars", "dither"), ("stars", "blend")] {
        let args = [wide.as_slice(), &["--view-distance", "10000", "--far-field", mesh, "--fade", fade]].concat();
        let (stdout, _) = render(&format!("10km-{mesh}-{fade}"), &args, &[]);
        let line = stdout.lines().find(|l| l.starts_with("far field: ")).expect("a far field line");
        assert!(line.contains("to 10000 m"), "{line}");
        // Zhang Xia's eq. 9: a ring's plants are as many as the next one's, so the count grows
        // with log(distance): well under the 20 000-triangle budget at the landscape camera.
        let triangles: u32 =
            line.split(", ").nth(1).and_then(|t| t.split(' ').next()).and_then(|n| n.parse().ok()).unwrap();
        assert!(triangles > 0 && triangles <= 20_000, "{line}");
    }
}

#[test]
fn under_opposite_winds_the_far_plants_shift_the_way_the_blades_do() {
    // Far plants from 5 m (blades to 6 m), or blades to 60 m: a steady strong wind across the
    // view, towards +x (right on screen) and towards -x.
    let base = CLOSE.to_vec();
    // The horizontal centre of the pixels `run` draws over the ground alone (blades to 6 m, no far
    // field) in the top third, where only plants past 6 m stand.
    let centre = |name: &str, extra: &[&str], wind: &str| -> f64 {
        let args = [base.as_slice(), extra, &["--wind", wind]].concat();
        let (_, picture) = render(&format!("{name}-{wind}"), &args, &[]);
        let ground = [base.as_slice(), &["--blade-distance", "6", "--far-field", "off", "--wind", wind]].concat();
        let (_, bare) = render(&format!("bare-{wind}"), &ground, &[]);
        let (mut sum, mut count) = (0.0, 0u32);
        for y in 0..picture.height / 3 {
            for x in 0..picture.width {
                let (a, b) = (picture.pixel(x, y), bare.pixel(x, y));
                if a.iter().zip(b).map(|(&p, q)| p.abs_diff(q) as u32).sum::<u32>() > 6 {
                    sum += f64::from(x);
                    count += 1;
                }
            }
        }
        assert!(count > 100, "{name} {wind}: {count} pixels");
        sum / f64::from(count)
    };
    let far = centre("far", &["--blade-distance", "6"], "0,1") - centre("far", &["--blade-distance", "6"], "180,1");
    let blades = centre("blades", &["--blade-distance", "60", "--far-field", "off"], "0,1")
        - centre("blades", &["--blade-distance", "60", "--far-field", "off"], "180,1");
    assert!(far > 1.0 && blades > 1.0, "shift right under +x wind: far field {far:.2} px, blades {blades:.2} px");
}

/// How much `pusher` (a source or a collider 25 m straight ahead, in a calm) spreads apart the
/// pixels that far plants (blades to 6 m) and blades (to 60 m) draw over the bare ground: the
/// distance between the left half's and the right half's horizontal centres, with it less without
/// it, in pixels (far field, blades). Plants left of it that lean left and those right of it that
/// lean right spread apart.
fn spread_gains(name: &str, pusher: &[&str]) -> (f64, f64) {
    let base = [CLOSE, &["--wind", "0,0"]].concat();
    let bare_args = [base.as_slice(), &["--blade-distance", "6", "--far-field", "off"]].concat();
    let (_, bare) = render(&format!("{name}-bare"), &bare_args, &[]);
    let spread = |name: &str, extra: &[&str]| -> f64 {
        let (_, picture) = render(name, &[base.as_slice(), extra].concat(), &[]);
        let (mut sums, mut counts) = ([0.0; 2], [0u32; 2]);
        for y in 0..picture.height / 3 {
            for x in 0..picture.width {
                let (a, b) = (picture.pixel(x, y), bare.pixel(x, y));
                if a.iter().zip(b).map(|(&p, q)| p.abs_diff(q) as u32).sum::<u32>() > 6 {
                    let half = usize::from(x >= picture.width / 2);
                    sums[half] += f64::from(x);
                    counts[half] += 1;
                }
            }
        }
        assert!(counts.iter().all(|&n| n > 30), "{name}: {counts:?}");
        sums[1] / f64::from(counts[1]) - sums[0] / f64::from(counts[0])
    };
    let far = ["--blade-distance", "6"];
    let blades = ["--blade-distance", "60", "--far-field", "off"];
    let far_gain =
        spread(&format!("{name}-far"), &[far.as_slice(), pusher].concat()) - spread(&format!("{name}-calm-far"), &far);
    let blades_gain = spread(&format!("{name}-blades"), &[blades.as_slice(), pusher].concat())
        - spread(&format!("{name}-calm-blades"), &blades);
    (far_gain, blades_gain)
}

#[test]
fn around_a_point_source_the_far_plants_lean_away_as_the_blades_do() {
    let (far_gain, blades_gain) = spread_gains("source", &["--source", "0,-25,3,1"]);
    assert!(
        far_gain > 1.0 && blades_gain > 1.0,
        "spread by the source: far field {far_gain:.2} px, blades {blades_gain:.2} px"
    );
}

#[test]
fn around_a_collider_the_far_plants_lean_away_as_the_blades_do() {
    // A sphere 20 m across, 25 m ahead on the ground: its push (not wind, and not
    // only its trail in the pressed map) leans the far plants round it outwards as it does the
    // blades (without the push in far.vert the far field's spread moved by 0.12 px, 2026-12-08).
    let (far_gain, blades_gain) = spread_gains("collider", &["--collider", "sphere:0,0,-25,10"]);
    assert!(
        far_gain > 1.0 && blades_gain > 1.0,
        "spread by the collider: far field {far_gain:.2} px, blades {blades_gain:.2} px"
    );
}

#[test]
fn a_cut_across_the_far_field_shortens_its_plants() {
    // Blades to 12 m, far plants from 7 m; a cut 8 m wide sweeps across the view 25 m ahead, past
    // the blades. With the far field the picture changes where it passed (the far plants read the
    // pressed map); without it nothing changes at all (the blades end short of the trail).
    let view = [
        "--field",
        "infinite",
        "--blade-distance",
        "12",
        "--view-distance",
        "200",
        "--camera",
        "0,3,0,0,-8",
        "--fog",
        "0.001",
        "--no-gusts",
        "--size",
        "320x180",
        "--time",
        "4",
    ];
    let cut: &[&str] = &["--cut", "sphere:-30,0,-25,4,15,0,0"];
    let changed = |extra: &[&str], name: &str| {
        let (_, whole) = render(&format!("{name}-whole"), &[view.as_slice(), extra].concat(), &[]);
        let (_, trail) = render(&format!("{name}-cut"), &[view.as_slice(), extra, cut].concat(), &[]);
        whole.rgb.chunks_exact(3).zip(trail.rgb.chunks_exact(3)).filter(|(a, b)| a != b).count()
    };
    let far = changed(&[], "far-cut");
    let off = changed(&["--far-field", "off"], "off-cut");
    assert!(far > 200, "the cut changed {far} pixels of the far field");
    assert_eq!(off, 0, "without a far field the cut, past the blades, changed the picture");
}

#[test]
fn a_covering_map_of_zero_grows_no_far_plant() {
    let dir = scratch("far-field-cover");
    for (name, grey) in [("bare", 0u8), ("full", 255u8)] {
        let map = dir.join(format!("{name}.png"));
        image::save_buffer(&map, &[grey; 64], 8, 8, image::ExtendedColorType::L8).expect("write map");
        let cover = ["--size", "320x180", "--terrain-scale", "5000,1,5000", "--cover", map.to_str().unwrap()];
        let args = [LANDSCAPE, &cover].concat();
        let (stdout, _) = render(&format!("cover-{name}"), &args, &[]);
        let plants = far_plants(&stdout);
        match grey {
            0 => assert_eq!(plants, 0, "{stdout}"),
            _ => assert!(plants > 100, "{stdout}"),
        }
    }
}

#[test]
fn the_far_flowers_follow_the_covering_map_s_green() {
    // Covering maps full of grass whose green (the flowers' density) is full west of x = 0 and
    // none east of it, the other way round, and full everywhere. All three bake one atlas (its
    // flower tiles at the share of full green), and a far plant takes the flower tiles where the
    // green is (`far.vert`): on a split map's green side its far rows are the all-green map's,
    // and on its other side they are not.
    let dir = scratch("far-field-flower-cover");
    let map = |name: &str, green: &dyn Fn(u32) -> u8| {
        let path = dir.join(format!("{name}.png"));
        let pixels: Vec<u8> = (0..64).flat_map(|x| [255, green(x), 0]).collect();
        image::save_buffer(&path, &pixels, 64, 1, image::ExtendedColorType::Rgb8).expect("write map");
        path
    };
    let west = map("west", &|x| if x < 32 { 255 } else { 0 });
    let east = map("east", &|x| if x < 32 { 0 } else { 255 });
    let all = map("all", &|_| 255);
    let picture = |name: &str, map: &std::path::Path| {
        let cover = ["--terrain-scale", "5000,1,5000", "--cover", map.to_str().expect("utf-8"), "--flowers", "20"];
        render(&format!("flower-cover-{name}"), &[LANDSCAPE, FULL, &cover].concat(), &[]).1
    };
    let (west, east, all) = (picture("west", &west), picture("east", &east), picture("all", &all));
    // The ground from 300 m to 1 km, in the left and right quarters of the picture (the camera
    // looks along -z: west is left), past the maps' seam.
    let rows = row_at(1000.0).ceil() as u32..=row_at(300.0).floor() as u32;
    let quarter = all.width / 8 / 4;
    let (left, right) = (0..quarter, 3 * quarter..4 * quarter);
    for (name, split, green, other) in [("west", &west, &left, &right), ("east", &east, &right, &left)] {
        let same = differing_blocks_in(split, &all, rows.clone(), green.clone());
        let apart = differing_blocks_in(split, &all, rows.clone(), other.clone());
        eprintln!("{name}: green side {same:.3}, other side {apart:.3} of the blocks differ");
        assert!(same <= 0.0, "{name}: the green side differs from the all-green map in {same:.3} of its blocks");
        assert!(apart >= 0.5, "{name}: the side without green differs in only {apart:.3} of its blocks");
    }
}

#[test]
fn the_atlas_is_baked_once_and_its_levels_keep_the_coverage() {
    // Three frames: the bake's passes run in the first alone.
    let args = [LANDSCAPE, &["--size", "320x180", "--frames", "3"]].concat();
    let (stdout, _) = render("frames", &args, &[]);
    let gpu = stdout.lines().find(|l| l.starts_with("gpu: ")).expect("a gpu line");
    assert!(!gpu.contains("far atlas") && gpu.contains("far field"), "the last of 3 frames baked again: {gpu}");
    let far = stdout.lines().find(|l| l.starts_with("far field: ")).expect("a far field line");
    assert!(far.contains("atlas baked in"), "{far}");
    // Every level's mean coverage is level 0's (box-filtered, premultiplied).
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (coverage, messages) = with_device(&options, false, |device| {
        let scene = Scene::blocks(FieldSpec { size: None, density: 100.0 }, 3);
        let culling = Culling { view_distance: 400.0, ..Culling::default_for(4) };
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let mut renderer = Renderer::new(Arc::clone(device), &scene, RenderSettings::offscreen(4, culling), animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 64, height: 36 })?;
        let camera = scene.camera(Some(CameraChoice::Landscape));
        renderer.render_offscreen(&mut target, &camera, 0.0)?;
        let coverage = renderer.far_atlas_coverage()?.expect("a far field");
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok(coverage)
    });
    let coverage = coverage.expect("render");
    assert_eq!(messages, Some(0));
    let base = coverage[0];
    assert!(base > 0.1 && base < 0.95, "level 0's coverage {base}");
    for (level, &mean) in coverage.iter().enumerate() {
        assert!((mean - base).abs() <= 0.02 * base, "level {level}: {mean:.4} against level 0's {base:.4}");
    }
}

#[test]
fn flowers_are_baked_into_the_atlas() {
    // `--flowers`: the blades the flowers claim are baked as stems under heads, so the atlas is
    // another (its coverage moves), and its levels still keep level 0's mean coverage.
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let mut coverages = Vec::new();
        for flowers in [None, Some(60.0)] {
            let mut scene = Scene::blocks(FieldSpec { size: None, density: 100.0 }, 3);
            if let Some(per_m2) = flowers {
                let flowers = meadow::scene::flowers::Flowers::new(per_m2).expect("flowers");
                scene = scene.with_flowers(flowers)?;
            }
            let culling = Culling { view_distance: 400.0, ..Culling::default_for(4) };
            let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
            let settings = RenderSettings::offscreen(4, culling);
            let mut renderer = Renderer::new(Arc::clone(device), &scene, settings, animation)?;
            let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 64, height: 36 })?;
            renderer.render_offscreen(&mut target, &scene.camera(Some(CameraChoice::Landscape)), 0.0)?;
            coverages.push(renderer.far_atlas_coverage()?.expect("a far field"));
            drop(renderer);
            // SAFETY: render_offscreen waited for its frame.
            unsafe { target.destroy(device) };
        }
        Ok(coverages)
    });
    let coverages = result.expect("render");
    assert_eq!(messages, Some(0));
    let (grass, flowers) = (coverages[0][0], coverages[1][0]);
    assert!((grass - flowers).abs() > 0.005 * grass, "the atlas with flowers: {flowers:.4} against {grass:.4}");
    for (level, &mean) in coverages[1].iter().enumerate() {
        assert!((mean - flowers).abs() <= 0.02 * flowers, "level {level}: {mean:.4} against {flowers:.4}");
    }
}

#[test]
fn a_rebuilt_renderer_keeps_the_baked_atlas() {
    // The viewer rebuilds the renderer for a new view distance or mesh: the blades, and so the
    // bake's key, are the same, so the new graph draws from the atlas the old one baked, with no
    // bake pass, and reads the same levels (validation and synchronization validation at 0: the
    // kept levels carry their states over, and nothing reads them undefined).
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let scene = Scene::blocks(FieldSpec { size: None, density: 100.0 }, 3);
        let culling = Culling { view_distance: 900.0, ..Culling::default_for(4) };
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let settings = RenderSettings::offscreen(4, culling);
        let mut renderer = Renderer::new(Arc::clone(device), &scene, settings, animation.clone())?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 64, height: 36 })?;
        let camera = scene.camera(Some(CameraChoice::Landscape));
        let bakes =
            |t: &meadow::render::FrameTimings| t.passes.iter().filter(|p| p.name.starts_with("far atlas")).count();
        let first = bakes(&renderer.render_offscreen(&mut target, &camera, 0.0)?);
        let before = renderer.far_atlas_coverage()?.expect("a far field");
        // Shorter: a longer view than the upload's needs a new renderer (`Renderer::fits_upload`).
        let nearer = Culling { view_distance: 400.0, far_field: meadow::render::far_field::FarField::Stars, ..culling };
        renderer.rebuild(&scene, RenderSettings { culling: nearer, ..settings }, animation)?;
        let timings = renderer.render_offscreen(&mut target, &camera, 0.0)?;
        let plants = renderer.far_counts()?.expect("a far field").plants;
        let after = renderer.far_atlas_coverage()?.expect("a far field");
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok((first, bakes(&timings), plants, before, after))
    });
    let (first, rebuilt, plants, before, after) = result.expect("render");
    assert_eq!(messages, Some(0));
    assert_eq!((first, rebuilt), (3, 0), "bake passes in the first frame, and after the rebuild");
    assert!(plants > 0, "the rebuilt far field draws");
    assert_eq!(before, after, "the kept atlas's levels");
}

#[test]
fn a_rebuild_past_the_uploaded_reach_is_refused_for_a_new_renderer() {
    // The cull's ring slots (the blade distance) and a block field's wind levels (the far
    // field's reach) are sized when the scene is uploaded: a rebuild that needs more is refused
    // (the viewer makes a new renderer instead, `Viewer::rebuild_passes`), so no far plant reads
    // the wind clamped at the old levels' edge and no ring is cut to the old capacity. Shorter
    // distances rebuild as before, and the refused rebuild leaves the renderer drawing.
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let scene = Scene::blocks(FieldSpec { size: None, density: 100.0 }, 3);
        let culling = Culling { view_distance: 1000.0, ..Culling::default_for(4) };
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let settings = RenderSettings::offscreen(4, culling);
        let mut renderer = Renderer::new(Arc::clone(device), &scene, settings, animation.clone())?;
        let with = |culling| RenderSettings { culling, ..settings };
        let farther = with(Culling { view_distance: 8000.0, ..culling });
        let blades = with(Culling { blade_distance: 300.0, ..culling });
        let nearer = with(Culling { view_distance: 400.0, blade_distance: 100.0, ..culling });
        let fits = [farther, blades, nearer].map(|s| renderer.fits_upload(&scene, &s));
        let refused = renderer.rebuild(&scene, farther, animation.clone()).err().map(|e| e.to_string());
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 64, height: 36 })?;
        let camera = scene.camera(Some(CameraChoice::Landscape));
        renderer.render_offscreen(&mut target, &camera, 0.0)?;
        let kept = renderer.far_counts()?.expect("a far field").rings.view_distance;
        renderer.rebuild(&scene, nearer, animation.clone())?;
        renderer.render_offscreen(&mut target, &camera, 0.0)?;
        let levels = renderer.wind_levels().len();
        drop(renderer);
        let wider = Renderer::new(Arc::clone(device), &scene, farther, animation)?;
        let wider_levels = wider.wind_levels().len();
        drop(wider);
        // SAFETY: render_offscreen waited for its frames.
        unsafe { target.destroy(device) };
        Ok((fits, refused, kept, levels, wider_levels))
    });
    let (fits, refused, kept, levels, wider_levels) = result.expect("render");
    assert_eq!(messages, Some(0));
    assert_eq!(fits, [false, false, true], "8 km view, 300 m of blades, then shorter, against an upload for 1 km");
    assert!(refused.as_deref().is_some_and(|e| e.contains("a new renderer")), "{refused:?}");
    assert_eq!(kept, 1000.0, "the refused rebuild kept the renderer's far field");
    assert!(wider_levels > levels, "a renderer for 8 km holds {wider_levels} wind levels, one for 1 km {levels}");
}

#[test]
fn the_blended_far_field_is_placed_far_to_near_in_the_keys_cpu_order() {
    // `--fade blend`: the placement's order is Zhang Xia's pre-computed one (`far_field::order`).
    // Each plant's key, recomputed on the CPU from where it stands, is the key the GPU kept;
    // the drawn order is the CPU's sort of those keys; and it runs far to near: the outer rings
    // first, and in a ring no plant comes after one nearer than itself by more than the order's
    // slack (the eye within half a step and a block of the order's place, a plant within a
    // quarter step of its point).
    use meadow::render::far_field::{order, FarFade};
    use meadow::render::field_gpu::Origin;
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let scene = Scene::blocks(FieldSpec { size: None, density: 100.0 }, 3);
        let culling = Culling { view_distance: 1200.0, far_fade: FarFade::Blend, ..Culling::default_for(4) };
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let mut renderer = Renderer::new(Arc::clone(device), &scene, RenderSettings::offscreen(4, culling), animation)?;
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 160, height: 90 })?;
        let mut camera = scene.camera(Some(CameraChoice::Landscape));
        // Off the lattice's lines and turned, so that no row of plants lies along the view.
        camera.position += glam::Vec3::new(37.3, 0.0, -11.9);
        camera.yaw_deg += 23.0;
        renderer.render_offscreen(&mut target, &camera, 0.0)?;
        let plants = renderer.far_plants()?.expect("a far field");
        drop(renderer);
        // SAFETY: render_offscreen waited for its frame.
        unsafe { target.destroy(device) };
        Ok((plants, camera, culling.far_rings().expect("rings")))
    });
    let (plants, camera, rings) = result.expect("render");
    assert_eq!(messages, Some(0));
    assert!(plants.len() > 100, "{} plants", plants.len());
    let origin = Origin::under(&camera);
    let eye = origin.relative(&camera).position;
    let ranks = order::ranks(&order::far_to_near(&rings));
    let cpu: Vec<u32> = plants
        .iter()
        .map(|p| {
            let at = (glam::Vec2::new(p.centre[0], p.centre[2]), glam::Vec2::new(eye.x, eye.z), origin.cell);
            order::key_of(&rings, &ranks, at).expect("a ring holds every plant")
        })
        .collect();
    let gpu: Vec<u32> = plants.iter().map(|p| p.key).collect();
    assert_eq!(cpu, gpu, "the keys recomputed on the CPU");
    let mut sorted = cpu.clone();
    sorted.sort_unstable();
    assert_eq!(gpu, sorted, "the drawn order is the CPU's sort of the keys");
    // Far to near: by ring from the outside, and in a ring within the slack.
    let mut nearest = std::collections::HashMap::new();
    for (p, key) in plants.iter().zip(&gpu) {
        let ring = rings.rings - 1 - key / order::PER_RING;
        let step = rings.step * (1u32 << ring) as f32;
        let offset = (glam::Vec2::new(p.centre[0], p.centre[2]) - glam::Vec2::new(eye.x, eye.z)).abs();
        let cheb = offset.x.max(offset.y);
        let least: &mut f32 = nearest.entry(ring).or_insert(f32::MAX);
        assert!(cheb <= *least + 1.5 * step, "ring {ring}: a plant at {cheb} m after one at {least} m");
        *least = least.min(cheb);
    }
    // More than one ring drawn, so the order across rings was tested too.
    let rings_drawn: std::collections::HashSet<u32> = gpu.iter().map(|key| key / order::PER_RING).collect();
    assert!(rings_drawn.len() > 1, "rings {rings_drawn:?}");
}

#[test]
fn the_band_trails_the_camera_on_a_leash_and_holds_still_while_it_jitters() {
    // The hysteresis of the band (`far_rings::BandEye`): a camera that crept up to a place sees
    // the band measured from a point a leash behind it, so its picture there differs from a
    // fresh renderer's; stepping back by less than the leash and forward again moves the band
    // not at all (the same picture to the bit, time fixed). A leash of 0 (stateless) sees the
    // fresh renderer's picture after the same creep.
    use meadow::render::far_rings::BAND_LEASH;
    let options = GpuOptions { validation: true, device: DeviceSelector::parse(support::DEVICE) };
    let (result, messages) = with_device(&options, false, |device| {
        let scene = Scene::blocks(FieldSpec { size: None, density: 100.0 }, 3);
        let animation = AnimationSettings { mode: Mode::Static, ..Default::default() };
        let mut target = OffscreenTarget::new(device, vk::Extent2D { width: 320, height: 180 })?;
        let camera = scene.camera(Some(CameraChoice::Landscape));
        let at =
            |dz: f32| meadow::scene::Camera { position: camera.position + glam::Vec3::new(0.0, 0.0, dz), ..camera };
        let mut pictures = Vec::new();
        for leash in [BAND_LEASH, 0.0] {
            let culling = Culling { view_distance: 600.0, band_leash: leash, ..Culling::default_for(4) };
            let settings = RenderSettings::offscreen(4, culling);
            let mut fresh = Renderer::new(Arc::clone(device), &scene, settings, animation.clone())?;
            fresh.render_offscreen(&mut target, &at(0.0), 0.0)?;
            let still = target.pixels().to_vec();
            drop(fresh);
            let mut crept = Renderer::new(Arc::clone(device), &scene, settings, animation.clone())?;
            // Up from 3 m behind in 0.25 m steps (the leash is 0.6 m), then 0.4 m back and on again.
            for step in (0..=12).rev() {
                crept.render_offscreen(&mut target, &at(0.25 * step as f32), 0.0)?;
            }
            let arrived = target.pixels().to_vec();
            crept.render_offscreen(&mut target, &at(0.4), 0.0)?;
            crept.render_offscreen(&mut target, &at(0.0), 0.0)?;
            pictures.push((still, arrived, target.pixels().to_vec()));
        }
        // SAFETY: render_offscreen waited for its frames.
        unsafe { target.destroy(device) };
        Ok(pictures)
    });
    let pictures = result.expect("render");
    assert_eq!(messages, Some(0));
    let (still, arrived, jittered) = &pictures[0];
    assert_ne!(arrived, still, "with a leash, the band trails a camera that crept up");
    assert_eq!(jittered, arrived, "a step back within the leash and forward again moved the band");
    let (still, arrived, jittered) = &pictures[1];
    assert_eq!(arrived, still, "without a leash, the band is the camera's own");
    assert_eq!(jittered, still);
}

#[test]
fn the_band_matches_the_blades_alone_shows_no_seam_and_no_flicker() {
    // `meadow bench --preset far`'s picture figures at 1280 × 720 (its costs are its own), for
    // the dither and blended, inside the bounds (1.5 % / 8 %, 0.5 % / 4 %, 1.5×). The
    // first implementation reached 0.50 % / 1.25 %, 0.41 % / 1.42 %, 1.39× (the bounds were then
    // 0.75 % / 2.5 %, 0.5 % / 2.5 %); with the first rings' plants half as long (2026-12-08,
    // `render::far_field::NEAR_WIDTH`) 0.30 % / 0.91 %, 0.25 % / 0.98 %, 0.92×, and past the band,
    // where the far field stands alone against the blades alone to 500 m, 0.28 % / 1.20 % (whole
    // length: 0.43 % / 1.47 %). The bounds are tightened to those with a margin.
    let out = scratch("far-field-bench").join("out");
    let output = support::meadow()
        .args([
            "bench",
            "--preset",
            "far",
            "--warmup",
            "0",
            "--frames",
            "1",
            "--validation",
            "--device",
            support::DEVICE,
        ])
        .arg("--out")
        .arg(&out)
        .output()
        .expect("run meadow");
    support::assert_clean(&output);
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("far.json")).expect("far.json")).expect("JSON");
    let p = &doc["pictures"];
    let f = |key: &str| p[key].as_f64().unwrap_or_else(|| panic!("{key}: {p}"));
    assert!(f("band_mean") <= 0.5 && f("band_p99") <= 1.5, "the band against the blades alone: {p}");
    assert!(f("seam_mean") <= 0.4 && f("seam_p99") <= 1.5, "the boundary moved by 20 %: {p}");
    assert!(f("past_mean") <= 0.4 && f("past_p99") <= 1.6, "past the band against the blades alone: {p}");
    // The creep past the band, across the rings' edges at 170 and 340 m, changes the far field
    // as much as it changes the blades alone there (0.99×, blended 0.53×, 2026-12-08).
    assert!(f("past_flicker_blades") > 0.0, "{p}");
    assert!(f("past_flicker_far") <= 1.2 * f("past_flicker_blades"), "the creep past the band: {p}");
    assert!(f("flicker_blades") > 0.0 && f("flicker_far") <= 1.2 * f("flicker_blades"), "the creep: {p}");
    // Blended (`--fade blend`), under the same bounds: first measured 0.49 % / 1.15 %,
    // 0.37 % / 1.15 %, 0.65×; now 0.30 % / 0.85 %, 0.24 % / 0.83 %, past the band 0.27 % / 1.10 %,
    // 0.54×.
    let b = |key: &str| p["blend"][key].as_f64().unwrap_or_else(|| panic!("blend {key}: {p}"));
    assert!(b("band_mean") <= 0.5 && b("band_p99") <= 1.5, "blended, the band against the blades alone: {p}");
    assert!(b("seam_mean") <= 0.4 && b("seam_p99") <= 1.5, "blended, the boundary moved by 20 %: {p}");
    assert!(b("past_mean") <= 0.4 && b("past_p99") <= 1.6, "blended, past the band: {p}");
    assert!(b("past_flicker_far") <= 1.2 * f("past_flicker_blades"), "blended, the creep past the band: {p}");
    assert!(b("flicker_far") <= 1.2 * f("flicker_blades"), "blended, the creep: {p}");
    // The blend is not the dither: its band differs from the blades alone otherwise.
    assert_ne!(b("band_mean"), f("band_mean"), "{p}");
}

#[test]
fn bad_far_fields_are_refused_in_one_line() {
    let cases: [(&[&str], &str); 9] = [
        (&["--field", "infinite", "--far-field", "trees"], "invalid value 'trees'"),
        (&["--field", "infinite", "--fade", "sorted"], "invalid value 'sorted'"),
        (
            &["--field", "infinite", "--view-distance", "600", "--fade", "blend", "--far-field", "off"],
            "--fade has no effect with --far-field off",
        ),
        (
            &["--field", "infinite", "--fade", "blend"],
            "--fade has no effect with stored blades or no ground past the blades",
        ),
        (&["--field", "infinite", "--far-field", "stars"], "--far-field has no effect with stored blades or no ground"),
        (&["--blade-distance", "3", "--view-distance", "10000"], "past the far field's reach"),
        (&["--blades", "500", "--far-field", "stars"], "--far-field has no effect with stored blades"),
        (&["--field", "infinite", "--blade-distance", "300", "--view-distance", "200"], "--blade-distance 300 is over"),
        // The blend's linear pair counts in the budget before anything is allocated.
        (
            &["--field", "infinite", "--view-distance", "600", "--fade", "blend", "--size", "10000x10000"],
            "with --fade blend's linear scene needs",
        ),
    ];
    for (args, why) in cases {
        let out = scratch("far-field-bad").join("never.png");
        let output = support::meadow()
            .arg("render")
            .args(args)
            .args(["--device", support::DEVICE])
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.starts_with("error: ") && stderr.contains(why), "{args:?}: {stderr}");
        assert!(!out.exists());
    }
}
