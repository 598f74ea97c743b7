//! Injected failures (`vk::fault`, `MEADOW_INJECT_*`): a memory allocation that runs out at any
//! point of start-up or rendering exits 1 with its own message, writes nothing, and destroys
//! everything it made (validation, which reports leaked objects at device destruction, stays
//! at 0 messages). Submission and surface failures: `tests/graph.rs`, `tests/viewer.rs`.

mod support;

use support::{meadow, scratch, transcript};

#[test]
fn running_out_of_memory_anywhere_exits_1_cleanly() {
    let dir = scratch("faults-alloc");
    let out = dir.join("x.png");
    let args = ["render", "--validation", "--device", support::DEVICE, "--blades", "2000", "--size", "64x64", "--out"];
    // The control: how many allocations a clean run makes is not fixed here, but it renders.
    let clean = meadow().args(args).arg(&out).output().expect("run");
    assert_eq!(clean.status.code(), Some(0), "{}", transcript(&clean));
    std::fs::remove_file(&out).expect("the control wrote its picture");
    // The first allocation, one during the scene upload, one of the frames and targets.
    for nth in ["1", "5", "12", "25"] {
        let output = meadow().args(args).arg(&out).env("MEADOW_INJECT_ALLOC_FAILURE", nth).output().expect("run");
        assert_eq!(output.status.code(), Some(1), "allocation {nth}: {}", transcript(&output));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            stderr.starts_with("error: allocating `")
                && stderr.contains("out of device memory")
                && stderr.lines().count() == 1,
            "allocation {nth}: {stderr}"
        );
        assert!(String::from_utf8_lossy(&output.stdout).contains("validation: 0 messages"), "{}", transcript(&output));
        assert!(!out.exists(), "allocation {nth}: a picture was written");
    }
}
