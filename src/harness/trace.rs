//! Chrome / Perfetto traces of measured frames: `meadow timing --trace` and the viewer's capture
//! button write the same format (CPU record, submit and fence wait; GPU frames and passes, on one
//! timeline through a calibrated or estimated mapping of the two clocks).

use std::time::Instant;

use serde_json::{json, Value};

use super::timing::{calibrate, estimated_mapping, ClockMapping, Frame, Run};
use crate::error::Result;
use crate::render::{FrameTimings, Renderer};
use crate::vk::Device;

/// The device clock's mapping to the CPU's, sampled now (`VK_EXT_calibrated_timestamps`) and
/// placed on `renderer`'s timeline; `None` without calibrated timestamps.
pub fn calibrated(device: &Device, renderer: &mut Renderer) -> Result<Option<ClockMapping>> {
    let period = f64::from(device.limits().timestamp_period);
    Ok(calibrate(device)?.map(|m| ClockMapping { gpu_ns: renderer.place_timestamp(m.gpu_ns as u64, period), ..m }))
}

/// The trace of `frames` (index and timings, in order) rendered with `frames_in_flight` in
/// flight between `started` and `ended`, placed with `mapping` or, without it, an estimated one.
pub fn of_frames(
    frames: Vec<(u32, FrameTimings)>,
    frames_in_flight: usize,
    mapping: Option<ClockMapping>,
    (started, ended): (Instant, Instant),
) -> Result<Value> {
    let frames: Vec<Frame> = frames.into_iter().map(|(index, timings)| Frame { index, timings }).collect();
    let mapping = match mapping {
        Some(mapping) => mapping,
        None => estimated_mapping(&frames, started, ended)?,
    };
    Ok(trace(&[Run { frames_in_flight, frames, mapping, started, ended }], started))
}

/// Chrome trace-event JSON (chrome://tracing, ui.perfetto.dev): process 1 is the CPU (record,
/// submit, fence wait per frame), process 2 the GPU (frame and passes); one thread per run.
pub(crate) fn trace(runs: &[Run], anchor: Instant) -> Value {
    let us = |s: f64| s * 1e6;
    let mut events = vec![
        json!({"ph": "M", "pid": 1, "name": "process_name", "args": {"name": "CPU"}}),
        json!({"ph": "M", "pid": 2, "name": "process_name", "args": {"name": "GPU (queue)"}}),
    ];
    for run in runs {
        let tid = run.frames_in_flight;
        let label = format!("{} frame(s) in flight", run.frames_in_flight);
        for pid in [1, 2] {
            events.push(json!({"ph": "M", "pid": pid, "tid": tid, "name": "thread_name", "args": {"name": label}}));
        }
        let since = |t: Instant| (t - anchor).as_secs_f64();
        for f in &run.frames {
            let t = &f.timings;
            let frame = format!("frame {}", f.index);
            if let Some([started, recorded, submitted]) = t.cpu_spans {
                events.push(json!({"ph": "X", "pid": 1, "tid": tid, "name": "record", "ts": us(since(started)),
                    "dur": us((recorded - started).as_secs_f64()), "args": {"frame": frame}}));
                events.push(json!({"ph": "X", "pid": 1, "tid": tid, "name": "submit", "ts": us(since(recorded)),
                    "dur": us((submitted - recorded).as_secs_f64()), "args": {"frame": frame}}));
            }
            if let Some([a, b]) = t.cpu_wait {
                events.push(json!({"ph": "X", "pid": 1, "tid": tid, "name": "fence wait", "ts": us(since(a)),
                    "dur": us((b - a).as_secs_f64()), "args": {"frame": frame}}));
            }
            let at = |ns: f64| us(run.mapping.seconds_since(anchor, ns));
            events.push(json!({"ph": "X", "pid": 2, "tid": tid, "name": frame, "ts": at(t.gpu_span_ns.0),
                "dur": (t.gpu_span_ns.1 - t.gpu_span_ns.0) * 1e-3,
                "args": {"clock": run.mapping.method, "deviation_ns": run.mapping.deviation_ns}}));
            for p in &t.passes {
                let mut args = json!({"frame": frame});
                if let Some(s) = p.statistics {
                    for (k, v) in s.fields() {
                        args[k] = json!(v);
                    }
                }
                events.push(json!({"ph": "X", "pid": 2, "tid": tid, "name": p.name, "ts": at(p.start_ns),
                    "dur": p.ms * 1e3, "args": args}));
            }
        }
    }
    json!({ "traceEvents": events, "displayTimeUnit": "ms" })
}
