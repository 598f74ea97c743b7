//! Injected failures (`vk::fault`, `MEADOW_INJECT_*`): device or host memory that runs out at any
//! point of start-up or rendering exits 1 with its own message, writes nothing, and destroys
//! everything it made (validation, which reports leaked objects at device destruction, stays
//! at 0 messages); a refused free fails the run. Submission and surface failures, and memory
//! running out in the middle of a viewer session: `tests/graph.rs`, `tests/viewer.rs`.

mod support;

use support::{meadow, scratch, transcript};

/// Make the N-th call of `variable`'s kind fail in a small render, for N = 1, 2, ... until a run
/// makes fewer such calls and renders: each failure exits 1 with one `error:` line that `said`
/// accepts, validation clean (leaks are reported at device destruction), and no picture. Returns
/// how many calls failed.
fn fail_each(name: &str, variable: &str, said: impl Fn(&str) -> bool) -> u32 {
    let dir = scratch(name);
    let out = dir.join("x.png");
    let args = ["render", "--validation", "--device", support::DEVICE, "--blades", "2000", "--size", "64x64", "--out"];
    // The control: how many calls a clean run makes is not fixed here, but it renders.
    let clean = meadow().args(args).arg(&out).output().expect("run");
    assert_eq!(clean.status.code(), Some(0), "{}", transcript(&clean));
    std::fs::remove_file(&out).expect("the control wrote its picture");
    let mut failed = 0;
    for nth in 1..=200 {
        let output = meadow().args(args).arg(&out).env(variable, nth.to_string()).output().expect("run");
        if output.status.code() == Some(0) {
            break;
        }
        failed += 1;
        assert_eq!(output.status.code(), Some(1), "{variable}={nth}: {}", transcript(&output));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.lines().count() == 1 && said(stderr.trim()), "{variable}={nth}: {stderr}");
        assert!(String::from_utf8_lossy(&output.stdout).contains("validation: 0 messages"), "{}", transcript(&output));
        assert!(!out.exists(), "{variable}={nth}: a picture was written");
    }
    assert!(out.exists(), "{variable}: the run past the last call renders");
    failed
}

#[test]
fn running_out_of_memory_anywhere_exits_1_cleanly() {
    // Every allocation in turn.
    let said = |e: &str| e.starts_with("error: allocating `") && e.contains("out of device memory");
    let failed = fail_each("faults-alloc", "MEADOW_INJECT_ALLOC_FAILURE", said);
    assert!(failed >= 20, "only {failed} allocations made");
}

#[test]
fn running_out_of_host_memory_exits_1_with_its_own_message() {
    // `MEADOW_INJECT_HOST_MEMORY_FAILURE=N`: the N-th vkCreateShaderModule (one per pipeline
    // stage) reports VK_ERROR_OUT_OF_HOST_MEMORY, every one in turn (this found a leaked pipeline
    // of the animation model when a pass after it failed).
    let expected =
        "error: vkCreateShaderModule (injected failure): out of host memory (try fewer blades, segments or pixels)";
    let failed = fail_each("faults-host", "MEADOW_INJECT_HOST_MEMORY_FAILURE", |e| e == expected);
    // Terrain, cull, poses and blades at least (two modules per graphics pipeline).
    assert!(failed >= 8, "only {failed} shader modules made");
}

#[test]
fn a_free_the_allocator_refuses_is_reported_and_fails_the_run() {
    // `MEADOW_INJECT_FREE_FAILURE=N`: the allocator reports an error for the N-th free. The
    // destructor cannot return it: it is logged, and the run exits 1 saying so.
    let dir = scratch("faults-free");
    let out = dir.join("x.png");
    let args = ["render", "--device", support::DEVICE, "--blades", "2000", "--size", "64x64", "--out"];
    let output = meadow().args(args).arg(&out).env("MEADOW_INJECT_FREE_FAILURE", "3").output().expect("run");
    assert_eq!(output.status.code(), Some(1), "{}", transcript(&output));
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("freeing the memory of `") && stderr.contains("injected failure"), "{stderr}");
    assert_eq!(stderr.lines().last(), Some("error: the allocator refused 1 free(s) (logged above)"), "{stderr}");
    // The control: the same run without the fault exits 0 and logs nothing.
    let output = meadow().args(args).arg(&out).output().expect("run");
    assert_eq!(output.status.code(), Some(0), "{}", transcript(&output));
    assert!(output.stderr.is_empty(), "{}", transcript(&output));
}
