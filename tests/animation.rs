//! Blades under forces: the CPU mirror of the vertex shader's chain (force → blade frame →
//! keyframe selection → tip), and renders of the keyframe paths through the real binary.

mod support;

use glam::{Vec2, Vec3};
use meadow::imagediff::compare_rgb;
use meadow::keyframes::{BladeModel, KeyframeLayout, KeyframeTable, Smoothing};
use meadow::render::animation;
use meadow::scene::clusters::ClusterGrid;
use meadow::scene::{bezier, Scene};
use meadow::wind::{Attenuation, CalmArea, Collider, GlobalWind, Wind};
use support::Picture;

/// World-space tip displacement of every blade under `wind` (height-scaled, as the shader does).
fn tip_displacements(scene: &Scene, wind: &Wind, attenuation: Attenuation) -> Vec<Vec3> {
    let table = KeyframeTable::generate(&BladeModel::new(4), KeyframeLayout::for_poses(1000));
    let grid = ClusterGrid::new(scene.terrain.size, 0.5);
    let corners = animation::corner_forces(&grid, wind, 0.0, attenuation);
    let emitters = animation::emitters(wind, 0.0);
    scene
        .blades
        .iter()
        .map(|b| {
            let root = Vec2::new(b.position[0], b.position[2]);
            let force = animation::blade_force(
                &grid,
                &grid.locate(root.x, root.y),
                &corners,
                &emitters,
                wind.sources.len(),
                attenuation,
                b,
            ) / b.stiffness;
            let (across, normal) = bezier::frame(b);
            let pose = table.pose_for(
                force.dot(Vec2::new(across.x, across.z)),
                force.dot(Vec2::new(normal.x, normal.z)),
                Smoothing::Nearest,
            );
            let d = pose.tip_displacement() * b.height;
            across * d.x + Vec3::Y * d.y + normal * d.z
        })
        .collect()
}

#[test]
fn wind_from_plus_x_moves_tips_towards_plus_x() {
    let scene = Scene::generate(2000, 3);
    let wind =
        Wind { global: Some(GlobalWind { direction_deg: 0.0, strength: 0.5, gusts: false }), ..Default::default() };
    let tips = tip_displacements(&scene, &wind, Attenuation::Cluster);
    for (i, d) in tips.iter().enumerate() {
        // An oblique blade also deflects along its soft (flapping) axis, so some z is expected.
        assert!(d.x > 0.02 && d.x > d.z.abs(), "blade {i} tip moved {d:?}");
    }
    let mean = tips.iter().sum::<Vec3>() / tips.len() as f32;
    assert!(mean.x > 0.1 && mean.z.abs() < 0.05 * mean.x, "mean tip displacement {mean:?}");
}

#[test]
fn blades_in_a_calm_area_stay_neutral() {
    let scene = Scene::generate(2000, 4);
    let calm = CalmArea { min: Vec2::new(-1.5, -1.5), max: Vec2::new(1.5, 1.5) };
    let wind = Wind {
        global: Some(GlobalWind { direction_deg: 45.0, strength: 0.8, gusts: true }),
        calm: vec![calm],
        ..Default::default()
    };
    let tips = tip_displacements(&scene, &wind, Attenuation::Cluster);
    let mut inside = 0;
    for (b, d) in scene.blades.iter().zip(&tips) {
        // Well inside: every corner of its 0.5 m cluster lies in the calm area.
        if b.position[0].abs() < 0.9 && b.position[2].abs() < 0.9 {
            inside += 1;
            assert!(d.length() < 2e-3 * b.height, "calm blade moved {d:?}");
        }
        if b.position[0].abs() > 2.2 || b.position[2].abs() > 2.2 {
            assert!(d.length() > 0.05 * b.height, "blade in the wind did not move");
        }
    }
    assert!(inside > 50);
}

#[test]
fn blades_near_a_collider_lean_away_from_it() {
    let scene = Scene::generate(2000, 6);
    // A sphere sitting on the ground (its Y is a world height): every blade under it reaches in.
    let center = Vec3::new(0.2, scene.terrain.height_at(0.2, -0.4) + 0.25, -0.4);
    let wind = Wind { colliders: vec![Collider::at_rest(center, Vec3::splat(0.3))], ..Default::default() };
    let tips = tip_displacements(&scene, &wind, Attenuation::Blade);
    let mut near = 0;
    for (b, d) in scene.blades.iter().zip(&tips) {
        let away = Vec2::new(b.position[0] - center.x, b.position[2] - center.z);
        if away.length() > 0.05 && away.length() < 0.25 {
            near += 1;
            assert!(Vec2::new(d.x, d.z).dot(away.normalize()) > 0.3 * d.length(), "blade at {away:?} leans {d:?}");
        }
    }
    assert!(near > 30);
}

fn render(name: &str, args: &[&str]) -> Picture {
    let dir = support::scratch(&format!("animation-{name}"));
    let path = dir.join("out.png");
    support::render(args, &path);
    Picture::load(&path)
}

/// Issue 29 item 3: a collider's Y is a world height. A sphere 50 m above the field changes no
/// pixel; the same sphere resting on the ground bends the blades under it. Culled (the GPU wind
/// field) and by brute force (the thesis' CPU corners).
#[test]
fn a_sphere_50_m_up_changes_no_pixel_and_one_on_the_ground_does() {
    let (x, z, radius) = (0.0f32, 1.5f32, 0.4f32);
    let terrain = meadow::scene::Terrain::generate(meadow::scene::blades::field_size(20000), 1);
    let ground = terrain.height_at(x, z);
    let sphere = |y: f32| format!("sphere:{x},{y},{z},{radius}");
    let (up, resting) = (sphere(ground + 50.0), sphere(ground + radius - 0.05));
    for (name, path) in [("culled", &[][..]), ("brute", &["--brute-force"][..])] {
        let base = [&["--blades", "20000", "--seed", "1", "--size", "160x96", "--time", "1"][..], path].concat();
        let without = render(&format!("{name}-none"), &base);
        let high = render(&format!("{name}-high"), &[&base[..], &["--collider", &up]].concat());
        let low = render(&format!("{name}-low"), &[&base[..], &["--collider", &resting]].concat());
        assert!(without.rgb == high.rgb, "{name}: a sphere 50 m up changed the picture");
        let (stats, _) = compare_rgb(&without.rgb, &low.rgb, 0);
        let changed = 1.0 - stats.within_fraction();
        assert!(changed > 0.003, "{name}: a sphere on the ground changed {:.3} % of the pixels", 100.0 * changed);
    }
}

#[test]
fn texture_uniform_and_both_evaluation_placements_give_the_same_picture() {
    let base = ["--blades", "6000", "--size", "200x120", "--wind", "10,0.6", "--no-gusts", "--time", "1"];
    fn with<'a>(base: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
        [base, extra].concat()
    }
    // Per vertex unless said otherwise (`--eval auto` is per drawn blade with the cull).
    let reference = render("float32", &with(&base, &["--encoding", "float32", "--eval", "vertex"]));
    for (name, extra) in [("unorm16", &["--encoding", "unorm16"][..]), ("rgba8x2", &["--encoding", "rgba8x2"][..])] {
        let other = render(name, &with(&base, &[extra, &["--eval", "vertex"][..]].concat()));
        let (stats, _) = compare_rgb(&reference.rgb, &other.rgb, 3);
        assert!(stats.within_fraction() > 0.97, "{name}: {:.2} % within ±3", 100.0 * stats.within_fraction());
    }
    // Evaluated once per blade and level in compute (snorm16 records), the blades land within a
    // quantisation step of the per-vertex evaluation, for both keyframe stores.
    for (name, extra) in [
        ("texture-blade", &["--encoding", "float32", "--eval", "blade"][..]),
        ("uniform-blade", &["--mode", "uniform", "--eval", "blade"][..]),
    ] {
        let per_vertex = if name.starts_with("uniform") {
            render("uniform-vertex", &with(&base, &["--mode", "uniform", "--eval", "vertex"]))
        } else {
            Picture { rgb: reference.rgb.clone(), ..reference }
        };
        let other = render(name, &with(&base, extra));
        let (stats, _) = compare_rgb(&per_vertex.rgb, &other.rgb, 3);
        assert!(stats.within_fraction() > 0.995, "{name}: {:.3} % within ±3", 100.0 * stats.within_fraction());
    }
    // Linear and spherical smoothing differ from each other far less than from no animation.
    let linear = render("linear", &with(&base, &["--smoothing", "linear"]));
    let slerp = render("slerp", &with(&base, &["--smoothing", "slerp"]));
    let (stats, _) = compare_rgb(&linear.rgb, &slerp.rgb, 3);
    eprintln!("linear vs slerp: {:.2} % within ±3", 100.0 * stats.within_fraction());
    assert!(stats.within_fraction() > 0.9, "linear vs slerp: {:.2} % within ±3", 100.0 * stats.within_fraction());
    // The animation is real: the static picture differs (static blades take no force flag:
    // `cli::effect` refuses them).
    let still = render("static", &["--blades", "6000", "--size", "200x120", "--mode", "static"]);
    let (stats, _) = compare_rgb(&reference.rgb, &still.rgb, 3);
    assert!(
        stats.within_fraction() < 0.8,
        "wind changed only {:.2} % of the picture",
        100.0 * (1.0 - stats.within_fraction())
    );
}

#[test]
fn curve_keyframes_work_at_any_segment_count_and_match_vertex_keyframes() {
    let base = ["--blades", "6000", "--size", "200x120", "--wind", "10,0.6", "--no-gusts"];
    let vertex = render("curve-vertex-16", &[&base[..], &["--segments", "16", "--eval", "vertex"]].concat());
    let curve =
        render("curve-16", &[&base[..], &["--segments", "16", "--keyframes", "curve", "--eval", "vertex"]].concat());
    let (stats, _) = compare_rgb(&vertex.rgb, &curve.rgb, 3);
    assert!(stats.within_fraction() > 0.9, "curve vs vertex at 16 segments: {:.2} %", 100.0 * stats.within_fraction());
    // One table for every segment count: 2 and 7 segments render from the same curve records.
    for segments in ["2", "7"] {
        let args = [&base[..], &["--segments", segments, "--keyframes", "curve", "--mode", "uniform"]].concat();
        let per_vertex = render(&format!("curve-{segments}"), &[&args[..], &["--eval", "vertex"]].concat());
        // The compute pass evaluates the curve at the same levels; the vertex shader then takes
        // its tangent from neighbouring levels instead of the curve's derivative, which shades
        // coarse (2-segment) blades slightly differently.
        let per_blade = render(&format!("curve-{segments}-blade"), &[&args[..], &["--eval", "blade"]].concat());
        let (stats, _) = compare_rgb(&per_vertex.rgb, &per_blade.rgb, 3);
        assert!(stats.within_fraction() > 0.98, "curve, {segments} segments: {:.3} %", 100.0 * stats.within_fraction());
    }
}

/// Render through the real binary; the picture and the `gpu:` line (its passes).
fn render_with_passes(name: &str, args: &[&str]) -> (Picture, String) {
    let dir = support::scratch(&format!("animation-{name}"));
    let path = dir.join("out.png");
    let output = support::render(args, &path);
    let stdout = String::from_utf8_lossy(&output.stdout).into_owned();
    let gpu = stdout.lines().find(|l| l.starts_with("gpu:")).unwrap_or_else(|| panic!("{name}: no gpu line: {stdout}"));
    (Picture::load(&path), gpu.to_string())
}

#[test]
fn with_the_cull_the_default_evaluates_each_drawn_blade_once() {
    // `--eval auto`: the blade-pose pass runs after the cull over its visible list (stored field
    // and block field alike); brute force keeps the thesis' per-vertex path.
    let wind = ["--wind", "10,0.6", "--no-gusts", "--time", "1", "--size", "200x120"];
    let stored = [&wind[..], &["--blades", "6000"]].concat();
    let (auto, passes) = render_with_passes("auto", &stored);
    assert!(passes.contains("blade poses"), "no pose pass with the cull: {passes}");
    // The drawn blades' levels are placed and lit once, after the poses (blade_levels.comp).
    assert!(passes.contains("blade poses") && passes.contains("blade levels"), "no levels pass: {passes}");
    assert!(passes.find("blade poses") < passes.find("blade levels"), "levels before poses: {passes}");
    let (per_vertex, passes) = render_with_passes("auto-vertex", &[&stored[..], &["--eval", "vertex"]].concat());
    assert!(!passes.contains("blade poses"), "--eval vertex ran the pose pass: {passes}");
    assert!(!passes.contains("blade levels"), "--eval vertex ran the levels pass: {passes}");
    let (_, passes) = render_with_passes("auto-brute", &[&stored[..], &["--brute-force"]].concat());
    assert!(!passes.contains("blade poses"), "brute force ran the pose pass: {passes}");
    // Brute force with per-blade records lights per vertex: the levels follow the cull's list.
    let (_, passes) = render_with_passes("brute-blade", &[&stored[..], &["--brute-force", "--eval", "blade"]].concat());
    assert!(passes.contains("blade poses") && !passes.contains("blade levels"), "brute force: {passes}");
    let (stats, _) = compare_rgb(&per_vertex.rgb, &auto.rgb, 3);
    assert!(stats.within_fraction() > 0.995, "stored: {:.3} % within ±3", 100.0 * stats.within_fraction());
    let still = render("auto-static", &["--size", "200x120", "--blades", "6000", "--mode", "static"]);
    let (stats, _) = compare_rgb(&still.rgb, &auto.rgb, 3);
    assert!(stats.within_fraction() < 0.9, "the per-blade records did not move the blades");
    // A block field: the records follow its cells' blades (ring slot and block blade).
    let field = [&wind[..], &["--field", "infinite"]].concat();
    let (blocks, passes) = render_with_passes("field-auto", &field);
    assert!(passes.contains("blade poses"), "no pose pass for a block field: {passes}");
    let (blocks_vertex, _) = render_with_passes("field-vertex", &[&field[..], &["--eval", "vertex"]].concat());
    let (stats, _) = compare_rgb(&blocks_vertex.rgb, &blocks.rgb, 3);
    assert!(stats.within_fraction() > 0.995, "field: {:.3} % within ±3", 100.0 * stats.within_fraction());
}
