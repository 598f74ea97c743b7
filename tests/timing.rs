//! GPU timing: timestamps bracket what they should (an empty span reads near zero, a known
//! workload does not), and `meadow timing` reports passes, statistics, frames in flight, a
//! histogram and a trace whose GPU spans nest, under validation; bad arguments exit 2.

mod support;

use ash::vk;
use meadow::app::{with_device, GpuOptions};
use meadow::vk::query::TimestampQueries;
use meadow::vk::{commands, sync, Access, Buffer, BufferDesc, DeviceSelector};
use serde_json::Value;
use support::{assert_clean, meadow, scratch, transcript};

#[test]
fn timestamps_of_an_empty_span_are_near_zero_and_of_a_fill_are_not() {
    let options = GpuOptions { validation: true, device: DeviceSelector::Name(support::DEVICE.into()) };
    let (result, validation) = with_device(&options, false, |device| {
        let size = 64 << 20;
        let target =
            Buffer::new(device, &BufferDesc::gpu_only("fill target", size, vk::BufferUsageFlags::TRANSFER_DST))?;
        let results = Buffer::new(device, &BufferDesc::readback("stamps", 64, vk::BufferUsageFlags::TRANSFER_DST))?;
        let mut stamps = TimestampQueries::new(device, "test stamps", 4)?;
        // Three submissions: lavapipe writes a timestamp from a CPU thread, so a busy machine can
        // preempt it inside the empty span; the least of three is the span's cost.
        let mut measure = || {
            commands::submit_and_wait(device, "timestamps", |cmd| {
                stamps.reset(device, cmd);
                stamps.write(device, cmd);
                stamps.write(device, cmd); // nothing between: an empty span
                                           // SAFETY: cmd is recording; the buffer is TRANSFER_DST and `size` bytes.
                unsafe { device.raw.cmd_fill_buffer(cmd, target.raw, 0, size, 0x3f80_0000) };
                stamps.write(device, cmd); // after 64 MiB written
                stamps.record_copy(device, cmd, results.raw, 0);
                let to_host = sync::buffer_barrier(results.raw, &[Access::TransferWrite], &[Access::HostRead]);
                sync::cmd_barriers(device, cmd, &[to_host], &[]);
                Ok(())
            })
            .map(|()| {
                let ticks = stamps.read_ticks(results.mapped());
                (stamps.elapsed_ms(ticks[0], ticks[1]), stamps.elapsed_ms(ticks[1], ticks[2]))
            })
        };
        let spans = (0..3).map(|_| measure()).collect::<meadow::error::Result<Vec<(f64, f64)>>>();
        // SAFETY: submit_and_wait waited for the GPU.
        unsafe {
            stamps.destroy(device);
            target.destroy(device);
            results.destroy(device);
        }
        spans
    });
    let runs = result.expect("timestamps");
    let (empty, fill) = runs.into_iter().min_by(|a, b| a.0.total_cmp(&b.0)).expect("three runs");
    assert_eq!(validation, Some(0), "validation messages");
    assert!(empty < 0.5, "empty span {empty} ms");
    assert!(fill > 0.0 && fill > empty, "64 MiB fill {fill} ms vs empty {empty} ms");
}

#[test]
fn timing_reports_passes_frames_in_flight_and_a_trace() {
    let dir = scratch("timing-tiny");
    let trace = dir.join("trace.json");
    let output = meadow()
        .args(["timing", "--validation", "--device", support::DEVICE, "--blades", "2000", "--segments", "4"])
        // The reference path: every blade drawn, so the statistics count all 2000 x 10 vertices.
        .arg("--brute-force")
        .args(["--size", "64x48", "--frames", "4", "--warmup", "1", "--out"])
        .arg(&dir)
        .arg("--trace")
        .arg(&trace)
        .output()
        .expect("run meadow timing");
    assert_clean(&output);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("in flight") && stdout.contains("blades"), "{stdout}");

    let doc: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("timing.json")).expect("timing.json")).expect("JSON");
    assert_eq!(doc["kind"], "timing");
    let passes: Vec<&str> =
        doc["passes"].as_array().expect("passes").iter().filter_map(|p| p["pass"].as_str()).collect();
    assert_eq!(passes, ["terrain", "blades"]);
    for p in doc["passes"].as_array().expect("passes") {
        assert!(p["gpu_ms"]["median"].as_f64().expect("median") > 0.0, "{p}");
    }
    assert_eq!(doc["pipeline_statistics"]["blades"]["vertex_invocations"], 2000 * 10);
    let runs = doc["frames_in_flight"].as_array().expect("runs");
    assert_eq!(runs.iter().map(|r| r["frames_in_flight"].as_u64().unwrap_or(0)).collect::<Vec<_>>(), [1, 2, 3]);
    for r in runs {
        assert_eq!(r["frames"], 4, "warm-up frames are dropped: {r}");
        assert!(r["fps"].as_f64().expect("fps") > 0.0);
        let busy = r["gpu_busy_fraction"].as_f64().expect("busy");
        assert!(busy > 0.0 && busy <= 1.0 + 1e-6, "{r}");
    }
    // One frame in flight: the CPU records only after the previous frame's fence, so its recording
    // overlaps no GPU work but for the clock mapping's microseconds of uncertainty.
    let alone = runs[0]["cpu_gpu_overlap_fraction"].as_f64().expect("overlap");
    assert!(alone < 0.1, "one frame in flight overlapped {alone}");
    let histogram = image::open(dir.join("timing.png")).expect("timing.png decodes");
    assert!(histogram.width() > 100 && histogram.height() > 100);

    // The trace: CPU and GPU processes; every pass lies within its frame's GPU span.
    let trace: Value = serde_json::from_str(&std::fs::read_to_string(&trace).expect("trace")).expect("trace JSON");
    let events = trace["traceEvents"].as_array().expect("events");
    let spans: Vec<&Value> = events.iter().filter(|e| e["ph"] == "X").collect();
    assert!(spans.iter().any(|e| e["pid"] == 1 && e["name"] == "record"));
    let frames: Vec<&&Value> =
        spans.iter().filter(|e| e["pid"] == 2 && e["name"].as_str().unwrap_or("").starts_with("frame")).collect();
    assert_eq!(frames.len(), 3 * 4);
    for pass in spans.iter().filter(|e| e["pid"] == 2 && (e["name"] == "terrain" || e["name"] == "blades")) {
        let frame = frames
            .iter()
            .find(|f| f["tid"] == pass["tid"] && f["name"] == pass["args"]["frame"])
            .expect("the pass's frame");
        let (fs, fd) = (frame["ts"].as_f64().unwrap(), frame["dur"].as_f64().unwrap());
        let (ps, pd) = (pass["ts"].as_f64().unwrap(), pass["dur"].as_f64().unwrap());
        assert!(ps >= fs - 1e-3 && ps + pd <= fs + fd + 1e-3, "{pass} outside {frame}");
    }
}

#[test]
fn bad_timing_arguments_exit_2() {
    for args in [
        &["timing", "--frames", "0"][..],
        &["timing", "--blades", "0"][..],
        &["timing", "--size", "0x10"][..],
        &["timing", "--submission", "mesh"][..],
        &["timing", "--clusters", "0"][..],
    ] {
        let output = meadow().args(args).output().expect("run");
        assert_eq!(output.status.code(), Some(2), "{args:?}: {}", transcript(&output));
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(stderr.starts_with("error: ") && stderr.lines().count() == 1, "{args:?}: {stderr}");
    }
}

/// With 2 and 3 frames in flight on one target, a pre-recorded command buffer must not be
/// resubmitted with the first frame's barriers (which discard the target), and secondaries must
/// be recorded per frame: synchronization validation watches both.
#[test]
fn reused_and_secondary_recordings_stay_valid_with_frames_in_flight() {
    for (strategy, clusters) in [("prerecorded", None), ("secondary", Some("10"))] {
        let dir = scratch(&format!("timing-{strategy}"));
        let output = meadow()
            .args(["timing", "--validation", "--device", support::DEVICE, "--blades", "3000", "--size", "64x48"])
            .args(["--frames", "4", "--warmup", "0", "--submission", strategy, "--brute-force"])
            .args(clusters.map(|n| ["--clusters", n]).into_iter().flatten())
            .arg("--out")
            .arg(&dir)
            .output()
            .expect("run meadow timing");
        assert_clean(&output);
    }
}

/// The GPU-driven path reports what its cull kept: every count after each test, and the drawn
/// blades per LOD bucket adding up to the total.
/// `meadow timing --validation ARGS --warmup 0` with `MEADOW_HIDE=hide`, clean; its timing.json.
fn timing_doc(name: &str, args: &[&str], hide: &str) -> Value {
    let dir = scratch(name);
    let output = meadow()
        .env("MEADOW_HIDE", hide)
        .args(["timing", "--validation", "--device", support::DEVICE, "--warmup", "0"])
        .args(args)
        .arg("--out")
        .arg(&dir)
        .output()
        .expect("run meadow timing");
    assert_clean(&output);
    serde_json::from_str(&std::fs::read_to_string(dir.join("timing.json")).expect("timing.json")).expect("JSON")
}

#[test]
fn timing_reports_the_cull_counts() {
    let doc = timing_doc("timing-cull", &["--blades", "5000", "--size", "160x90", "--frames", "2"], "");
    let cull = &doc["cull"];
    let n = |k: &str| cull[k].as_u64().unwrap_or_else(|| panic!("{k} in {cull}"));
    assert_eq!(n("considered"), 5000);
    let chain = ["considered", "after_tiles", "after_density", "after_frustum", "after_orientation", "after_occlusion"];
    for pair in chain.windows(2) {
        assert!(n(pair[1]) <= n(pair[0]), "{pair:?}: {cull}");
    }
    let buckets: u64 =
        cull["buckets"].as_array().expect("buckets").iter().map(|b| b["drawn"].as_u64().unwrap_or(0)).sum();
    assert_eq!(buckets, n("drawn"));
    assert_eq!(n("drawn"), n("after_occlusion"));
    assert!(n("drawn") > 0 && n("drawn") < 5000, "{cull}");
    // The visible list holds every kept blade: nothing thinned, nothing without verdict room.
    assert_eq!((cull["capacity_scale"].as_f64(), n("wanted"), n("no_room")), (Some(1.0), n("drawn"), 0), "{cull}");
}

#[test]
fn the_frame_time_is_the_passes_and_the_read_back_copy_is_apart() {
    // `gpu:` spans the passes only: their times and the time between them add up to it, read
    // from the same timestamps (only the 3-decimal rounding differs). The copy of the picture to
    // the host after the last pass is reported on its own: were it inside `gpu:`, the sum would
    // miss it. No bound on the time between passes: it depends on the machine's load.
    let dir = support::scratch("timing-readback");
    let output = support::render(&["--blades", "3000", "--size", "640x360"], &dir.join("x.png"));
    let stdout = String::from_utf8_lossy(&output.stdout);
    let line = stdout.lines().find(|l| l.starts_with("gpu: ")).expect("a gpu line");
    let numbers: Vec<f64> =
        line.split(|c: char| !(c.is_ascii_digit() || c == '.')).filter_map(|w| w.parse().ok()).collect();
    let (frame, parts, copy) = (numbers[0], &numbers[1..numbers.len() - 1], numbers[numbers.len() - 1]);
    let sum: f64 = parts.iter().sum();
    assert!(line.contains("; between passes ") && line.contains("); read-back copy ") && parts.len() >= 3, "{line}");
    let rounding = 0.0005 * (parts.len() + 1) as f64 + 1e-6;
    assert!((frame - sum).abs() <= rounding, "frame {frame} ms, passes and between {sum} ms: {line}");
    assert!(copy > 0.0, "the copy of 640x360 pixels took no time: {line}");
}

#[test]
fn a_wrapping_timestamp_counter_keeps_the_timeline_in_order() {
    // `MEADOW_HIDE=timestampValidBits=26`: the counter wraps every 2^26 ns (67 ms), as a GPU with
    // few valid bits does. Each run lasts longer than two wraps, so its frames cross one: spans are
    // subtracted modulo the bits, and frames are placed on an unwrapped timeline (before, a wrap
    // read as a frame 2^26 ns long or going back in time: 0 fps, -162 % GPU busy).
    let args = ["--blades", "300", "--size", "32x32", "--frames", "120"];
    let doc = timing_doc("timing-wrap", &args, "timestampValidBits=26");
    assert_eq!(doc["timestamp_valid_bits"], 26);
    let wrap_s = (1u64 << 26) as f64 * 1e-9;
    for run in doc["frames_in_flight"].as_array().expect("runs") {
        let f = |k: &str| run[k].as_f64().unwrap_or_else(|| panic!("{k} in {run}"));
        assert!(f("wall_s") > 2.0 * wrap_s, "the run did not last two wraps: {run}");
        let (busy, overlap) = (f("gpu_busy_fraction"), f("cpu_gpu_overlap_fraction"));
        assert!(busy > 0.05 && busy <= 1.0 + 1e-9, "GPU busy {busy}: {run}");
        assert!((0.0..=1.0).contains(&overlap), "overlap {overlap}: {run}");
        let fps = f("fps");
        let expected = 120.0 / f("wall_s");
        assert!(fps > 0.3 * expected && fps < 3.0 * expected, "fps {fps} against {expected} frames per wall second");
        let interval = &run["frame_interval_ms"];
        let (p5, max) = (interval["p5"].as_f64().expect("p5"), interval["max"].as_f64().expect("max"));
        assert!(p5 > 0.0 && max < wrap_s * 1e3, "intervals {interval}");
    }
}
