//! The viewer's frame statistics: averaged per half second into the window title and every
//! few seconds onto stdout.

use std::time::{Duration, Instant};

use winit::window::Window;

use crate::render::FrameTimings;

/// Frame statistics, reported twice a second in the title and every few seconds on stdout.
pub(super) struct Stats {
    since_title: Instant,
    since_print: Instant,
    frames: u32,
    cpu_ms: f64,
    gpu_ms: f64,
    /// Whether the last frame's GPU times were measured (the queue writes timestamps).
    gpu_available: bool,
    passes: Vec<(&'static str, f64)>,
    /// The cull's counts of the last frame read back, if the cull ran.
    cull: Option<crate::render::culling::CullCounts>,
    pub(super) last: String,
}

impl Stats {
    pub(super) fn new() -> Self {
        Self {
            since_title: Instant::now(),
            since_print: Instant::now(),
            frames: 0,
            cpu_ms: 0.0,
            gpu_ms: 0.0,
            gpu_available: true,
            passes: Vec::new(),
            cull: None,
            last: String::new(),
        }
    }

    pub(super) fn add(&mut self, t: &FrameTimings) {
        self.frames += 1;
        self.cpu_ms += t.cpu_record_ms + t.cpu_submit_ms + t.cpu_wait_ms;
        self.gpu_ms += t.gpu_ms;
        self.gpu_available = t.gpu_available;
        self.cull = t.cull;
        for p in &t.passes {
            match self.passes.iter_mut().find(|(n, _)| *n == p.name) {
                Some(entry) => entry.1 += p.ms,
                None => self.passes.push((p.name, p.ms)),
            }
        }
    }

    /// Every half second: the averages since the last line, for the title (and every 3 s, stdout).
    pub(super) fn tick(&mut self, window: &Window, blades: u32, triangles: u64, device: &str) {
        let elapsed = self.since_title.elapsed().as_secs_f64();
        if elapsed < 0.5 || self.frames == 0 {
            return;
        }
        let n = f64::from(self.frames);
        let passes: Vec<String> = self.passes.iter().map(|(name, ms)| format!("{name} {:.2}", ms / n)).collect();
        let drawn = match &self.cull {
            Some(cull) => format!("cull: {}", cull.summary()),
            None => format!("{blades} blades, {triangles} triangles (brute force)"),
        };
        let gpu = match self.gpu_available {
            true => format!("gpu {:.2} ms ({})", self.gpu_ms / n, passes.join(", ")),
            false => "gpu unavailable (no timestamps)".to_string(),
        };
        self.last = format!("{:.1} fps, cpu {:.2} ms, {gpu}, {drawn}, {device}", n / elapsed, self.cpu_ms / n);
        window.set_title(&format!("meadow - {}", self.last));
        if self.since_print.elapsed() >= Duration::from_secs(3) {
            println!("stats: {}", self.last);
            self.since_print = Instant::now();
        }
        *self = Self { since_print: self.since_print, last: std::mem::take(&mut self.last), ..Self::new() };
    }
}

/// The soak's sample after `frame` frames: the process's resident memory (`VmRSS` of
/// `/proc/self/status`, 0 where there is none), the Vulkan objects alive (`vk::live`), in all and
/// by type, and the allocations made so far.
pub(super) fn sample(frame: u64) -> String {
    let rss_kib = std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| s.lines().find_map(|l| l.strip_prefix("VmRSS:")?.trim().strip_suffix("kB")?.trim().parse().ok()))
        .unwrap_or(0u64);
    let allocations = crate::vk::fault::calls(crate::vk::fault::Fault::Allocation);
    let by_type: Vec<String> = crate::vk::live::by_type().iter().map(|(t, n)| format!("{t}={n}")).collect();
    format!(
        "sample: frame {frame} rss_kib {rss_kib} live_vulkan_objects {} by_type {} allocations {allocations}",
        crate::vk::live::total(),
        by_type.join(",")
    )
}
