//! The backend profiles (`vk::profile::Profile`): the generic one, which binds each resource once
//! as its shader reads it, draws the lavapipe profile's pictures on lavapipe, validation-clean;
//! `MEADOW_PROFILE` chooses, and a value it does not know is refused.

mod support;

use std::process::Output;

fn render(profile: &str, args: &[&str], name: &str) -> (Output, support::Picture) {
    let dir = support::scratch(&format!("profiles_{name}_{profile}"));
    let out = dir.join("out.png");
    let output = support::meadow()
        .env("MEADOW_PROFILE", profile)
        .arg("render")
        .args(["--validation", "--device", support::DEVICE])
        .args(args)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("run meadow");
    support::assert_clean(&output);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains(&format!(", profile {profile}\n")), "the profile is not {profile}:\n{stdout}");
    (output, support::Picture::load(&out))
}

fn same_pictures(args: &[&str], name: &str) {
    let (_, lavapipe) = render("lavapipe", args, name);
    let (_, generic) = render("generic", args, name);
    assert_eq!((lavapipe.width, lavapipe.height), (generic.width, generic.height));
    let differing = lavapipe.rgb.iter().zip(&generic.rgb).filter(|(a, b)| a != b).count();
    // Every value read is the same bits through either binding: the pictures are the same.
    assert_eq!(differing, 0, "{name}: {differing} channels differ between the profiles");
}

#[test]
fn a_culled_stored_field_evaluated_per_blade_is_the_same_in_both_profiles() {
    // The cull (frame, depth pyramid, verdicts), pose records, placed levels and the blades.
    same_pictures(&["--blades", "20000", "--size", "320x180", "--seed", "1", "--eval", "blade"], "stored");
}

#[test]
fn a_block_field_is_the_same_in_both_profiles() {
    // The relief grid, read by the terrain, the cull and the blades' lighting.
    let args = ["--size", "320x180", "--field", "infinite", "--camera", "0,3,20,0,-15", "--mode", "static"];
    same_pictures(&args, "field");
}

#[test]
fn an_unknown_profile_is_refused_with_one_line() {
    let dir = support::scratch("profiles_unknown");
    let out = dir.join("out.png");
    let output = support::meadow()
        .env("MEADOW_PROFILE", "fast")
        .args(["render", "--device", support::DEVICE, "--blades", "100", "--size", "64x36", "--out"])
        .arg(&out)
        .output()
        .expect("run meadow");
    assert_eq!(output.status.code(), Some(2), "{}", support::transcript(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.starts_with("error: MEADOW_PROFILE=\"fast\""), "{stderr}");
    assert!(!out.exists(), "nothing is written");
}
