//! Set 0's bindings come from their declarations, not from a hand-kept list: `build.rs` numbers
//! every `layout(SCENE(Name), …)` it finds (`build/scene_set.rs`, tested here on texts), and a
//! resource declared in one header, by a test alone (`tests/shaders/scene_set/probe_words.glsl`),
//! gets its binding from build.rs and is written by name on lavapipe, with validation on.

#[path = "support/compute.rs"]
mod compute;
#[path = "../build/scene_set.rs"]
mod scene_set;

use std::sync::Arc;

use ash::vk;
use meadow::app::{with_device, GpuOptions};
use meadow::render::layouts;
use meadow::vk::descriptor::{Resource, SetLayout};
use meadow::vk::{pipeline, reflect, Buffer, BufferDesc, Device, DeviceSelector};
use scene_set::{declarations, header, numbers};

const PROBE: meadow::vk::profile::Shader = meadow::spirv_shader!("tests/scene_set/probe.comp");

/// build.rs's numbers (`generated/scene_set.glsl`).
fn generated() -> Vec<(String, u32)> {
    include_str!(concat!(env!("OUT_DIR"), "/glsl/generated/scene_set.glsl"))
        .lines()
        .filter_map(|l| l.strip_prefix("#define SCENE_BINDING_"))
        .map(|l| {
            let mut words = l.split_whitespace();
            (words.next().unwrap().to_owned(), words.next().unwrap().parse().unwrap())
        })
        .collect()
}

#[test]
fn set_0_is_numbered_by_build_rs_from_its_owners_declarations() {
    let numbers = generated();
    for profile in [meadow::vk::profile::Profile::Lavapipe, meadow::vk::profile::Profile::Generic] {
        let (scene, _) = layouts::scene_bindings(profile).unwrap();
        for (binding, name) in &scene {
            let generated = numbers.iter().find(|(n, _)| n == name);
            assert_eq!(generated.map(|(_, b)| *b), Some(binding.binding), "{profile:?} `{name}`: {numbers:?}");
        }
    }
    // Declared in their owners' headers (terrain/ground_texels.glsl, animation/frame_forces.glsl),
    // none of them in shared.glsl.
    for name in ["GroundTexels", "Corners", "Emitters", "Frame", "Tiles", "blade_alpha"] {
        assert!(numbers.iter().any(|(n, _)| n == name), "{name}: {numbers:?}");
    }
    let shared = include_str!("../shaders/common/shared.glsl");
    assert!(!shared.contains("SET_SCENE, binding") && !shared.contains("BINDING_FRAME"), "set 0 is numbered by hand");
    // Distinct numbers, the library's from 0.
    let mut seen: Vec<u32> = numbers.iter().map(|(_, b)| *b).collect();
    seen.sort();
    seen.dedup();
    assert_eq!(seen.len(), numbers.len(), "{numbers:?}");
}

#[test]
fn names_are_numbered_by_name_the_librarys_first() {
    let library = "// a comment: SCENE(Ignored) is not a declaration\n\
                   layout(SCENE(Zeta), std430) readonly buffer Zeta { float z[]; };\n\
                   layout(SCENE(alpha)) uniform sampler2D alpha;\n\
                   #define NOT_A_DECLARATION SCENE(x)\n";
    let other = "layout(SCENE(Frame), std140) uniform Frame { vec4 f; };\n\
                 layout(SCENE(Zeta), std430) writeonly buffer Zeta { float z[]; };\n";
    let test = "layout(SCENE(Aardvark), std430) buffer Aardvark { uint a[]; };\n";
    let mut all = declarations("shaders/a.glsl", library, true).unwrap();
    all.extend(declarations("shaders/b.glsl", other, true).unwrap());
    all.extend(declarations("tests/shaders/t.glsl", test, false).unwrap());
    let kinds: Vec<&str> = all.iter().map(|d| d.kind.as_str()).collect();
    assert_eq!(kinds, ["buffer", "sampler2D", "uniform", "buffer", "buffer"]);
    let numbered: Vec<(String, u32)> = numbers(&all).unwrap().into_iter().map(|(n, b, _)| (n, b)).collect();
    let expected = [("Frame", 0), ("Zeta", 1), ("alpha", 2), ("Aardvark", 3)];
    assert_eq!(numbered, expected.map(|(n, b)| (n.to_owned(), b)));
    // The order of the files does not matter.
    all.reverse();
    let again: Vec<(String, u32)> = numbers(&all).unwrap().into_iter().map(|(n, b, _)| (n, b)).collect();
    assert_eq!(again, numbered);
    let text = header(&all).unwrap();
    assert!(text.contains("#define SCENE(name) set = SET_SCENE, binding = SCENE_BINDING_##name"), "{text}");
    assert!(text.contains("#define SCENE_BINDING_alpha 2 // sampler2D, shaders/a.glsl:3\n"), "{text}");
}

#[test]
fn one_name_declared_as_two_kinds_fails_naming_both() {
    let a = "layout(SCENE(Visible), std430) readonly buffer Visible { uvec2 visible[]; };\n";
    let b = "\n\nlayout(SCENE(Visible)) uniform usamplerBuffer Visible;\n";
    let mut all = declarations("shaders/cull/visible.glsl", a, true).unwrap();
    all.extend(declarations("shaders/blades/other.glsl", b, true).unwrap());
    let error = numbers(&all).unwrap_err();
    assert!(error.contains("shaders/cull/visible.glsl:1") && error.contains("shaders/blades/other.glsl:3"), "{error}");
    assert!(error.contains("`Visible` is a buffer here and a usamplerBuffer"), "{error}");
    assert!(header(&all).is_err());
}

#[test]
fn a_declaration_build_rs_cannot_read_fails_with_its_line() {
    for (text, why) in [
        ("layout(SCENE(Heights), std430) readonly buffer Height { float h[]; };", "declares `Height`"),
        ("layout(std430, SCENE(Heights)) buffer Heights { float h[]; };", "SCENE first"),
        ("layout(SCENE(Heights), std430) buffer Heights", "on this line"),
        ("layout(SCENE(2x)) uniform sampler2D x;", "GLSL name"),
        ("layout(SCENE(x)) uniform sampler2D;", "expected"),
    ] {
        let error = declarations("shaders/t.glsl", &format!("// header\n{text}\n"), true).unwrap_err();
        assert!(error.starts_with("shaders/t.glsl:2: ") && error.contains(why), "{text}: {error}");
    }
}

/// The probe's set 0 on the GPU: `Corners` (a buffer of one vec4, 2.5 in its y) and `ProbeWords`,
/// given by name; the words it wrote.
fn run_probe(device: &Arc<Device>) -> meadow::Result<Vec<u32>> {
    let code = PROBE.code(device.profile);
    let set_layout = SetLayout::reflected(device, "probe set layout", &[("probe.comp", code)], 0)?;
    let layout = pipeline::layout(device, "probe layout", &[set_layout.raw], &[])?;
    let pipe = pipeline::compute(device, "scene set probe", code, layout, &[])?;
    let (pool, sets) = set_layout.allocate(device, "probe", 1)?;
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let corners = Buffer::with_data(device, &BufferDesc::upload("probe corners", 16, usage), &[0.0f32, 2.5, 0.0, 0.0])?;
    let out = Buffer::new(device, &BufferDesc::readback("probe words", 12, usage))?;
    // A binding with nothing given is refused, naming it.
    let missing =
        set_layout.write_named(device, sets[0], "probe set", &[("Corners", Resource::Buffer(corners.descriptor()))]);
    let named =
        [("ProbeWords", Resource::Buffer(out.descriptor())), ("Corners", Resource::Buffer(corners.descriptor()))];
    let written = set_layout.write_named(device, sets[0], "probe set", &named);
    let result =
        written.and_then(|()| compute::dispatch(device, "scene set probe", (pipe, layout), &sets, &[], 1, out.raw));
    let words = bytemuck::cast_slice::<u8, u32>(out.mapped()).to_vec();
    // SAFETY: dispatch waited (or nothing was submitted).
    unsafe { compute::teardown(device, (pool, pipe, layout, set_layout.raw), [corners, out]) };
    let error = missing.expect_err("ProbeWords was not given").to_string();
    assert!(error.contains("`ProbeWords`"), "{error}");
    result.map(|()| words)
}

#[test]
fn a_resource_declared_in_one_header_is_numbered_by_build_rs_and_written_by_name() {
    let numbers = generated();
    let number = |name: &str| numbers.iter().find(|(n, _)| n == name).map(|(_, b)| *b);
    let probe_words = number("ProbeWords").expect("build.rs numbered the test's own resource");
    let corners = number("Corners").expect("build.rs numbered Corners");
    let options = GpuOptions { validation: true, device: DeviceSelector::parse("llvmpipe") };
    let (result, messages) = with_device(&options, false, |device| {
        // The library's scene layout (reflected, names included) holds Corners at build.rs's
        // number, and not the test's resource; the test's names come after the library's.
        let (scene, _) = layouts::scene_bindings(device.profile)?;
        let library = scene.iter().find(|(_, n)| n == "Corners").map(|(b, _)| b.binding);
        assert_eq!(library, Some(corners));
        assert!(scene.iter().all(|(b, n)| n != "ProbeWords" && b.binding < probe_words), "{scene:?}");
        let reflected = reflect::reflect("probe.comp", PROBE.code(device.profile))?.descriptors;
        let found: Vec<(u32, &str)> = reflected.iter().map(|d| (d.binding, d.name.as_str())).collect();
        let mut expected = vec![(corners, "Corners"), (probe_words, "ProbeWords")];
        expected.sort();
        assert_eq!(found, expected);
        run_probe(device)
    });
    let words = result.expect("the probe ran");
    assert_eq!(messages, Some(0), "validation messages");
    assert_eq!(words, [probe_words, corners, 2.5f32.to_bits()]);
}

#[test]
fn specialization_constants_are_numbered_by_name_and_checked() {
    use scene_set::{spec_declarations, spec_header};
    let common = "layout(constant_id = SPEC(SEGMENTS)) const uint SEGMENTS = 4u;\n\
                  layout(constant_id = SPEC(STRIP_AREA)) const float STRIP_AREA = 1.0;\n\
                  layout(local_size_x_id = SPEC(SEGMENTS)) in; // a use, not a declaration\n\
                  layout(constant_id = 0) const bool OWN = false; // one shader's own id\n";
    let all = spec_declarations("shaders/common/common.glsl", common, true).unwrap();
    let names: Vec<(&str, &str)> = all.iter().map(|d| (d.name.as_str(), d.kind.as_str())).collect();
    assert_eq!(names, [("SEGMENTS", "uint"), ("STRIP_AREA", "float")]);
    let text = spec_header(&all).unwrap();
    assert!(text.contains("#define SPEC(name) SPEC_ID_##name"), "{text}");
    assert!(text.contains("#define SPEC_ID_SEGMENTS 0 // uint, shaders/common/common.glsl:1\n"), "{text}");
    assert!(text.contains("#define SPEC_ID_STRIP_AREA 1 "), "{text}");
    // One name, two types: refused, naming both.
    let mut clash = all.clone();
    let other = "layout(constant_id = SPEC(SEGMENTS)) const float SEGMENTS = 4.0;\n";
    clash.extend(spec_declarations("tests/shaders/t.comp", other, false).unwrap());
    let error = spec_header(&clash).unwrap_err();
    assert!(error.contains("common.glsl:1") && error.contains("tests/shaders/t.comp:1"), "{error}");
    // A name that is not the constant's.
    let wrong = "layout(constant_id = SPEC(SEGMENTS)) const uint SEGMENT = 4u;\n";
    let error = spec_declarations("shaders/x.glsl", wrong, true).unwrap_err();
    assert!(error.starts_with("shaders/x.glsl:1: ") && error.contains("SPEC(SEGMENTS)"), "{error}");
}
