//! The overlay's timing panel: the last frames' GPU time per pass as a live stacked graph, the
//! CPU's record / submit / wait, percentiles of the frame time, and the cull's counts.

use std::collections::VecDeque;

use egui::{Color32, Rect, Sense, Stroke, Ui, Vec2};

use crate::render::culling::CullCounts;
use crate::render::FrameTimings;
use crate::vk::query::PipelineStatistics;

/// Frames the graph and the percentiles cover.
pub const HISTORY: usize = 240;

/// One frame as the panel keeps it.
struct Sample {
    gpu_ms: f64,
    passes: Vec<(&'static str, f64)>,
    cpu: [f64; 3],
}

/// The last `HISTORY` frames' timings.
#[derive(Default)]
pub struct TimingHistory {
    samples: VecDeque<Sample>,
    /// Every pass seen, in first-seen order (stable colours).
    names: Vec<&'static str>,
    cull: Option<CullCounts>,
    gpu_available: bool,
    /// The last frame's pipeline statistics per counted pass.
    statistics: Vec<(&'static str, PipelineStatistics)>,
}

impl TimingHistory {
    /// Keep `t` (a frame's timings read after its fence).
    pub fn add(&mut self, t: &FrameTimings) {
        for p in &t.passes {
            if !self.names.contains(&p.name) {
                self.names.push(p.name);
            }
        }
        if self.samples.len() == HISTORY {
            self.samples.pop_front();
        }
        self.samples.push_back(Sample {
            gpu_ms: t.gpu_ms,
            passes: t.passes.iter().map(|p| (p.name, p.ms)).collect(),
            cpu: [t.cpu_record_ms, t.cpu_submit_ms, t.cpu_wait_ms],
        });
        self.cull = t.cull;
        self.gpu_available = t.gpu_available;
        self.statistics = t.passes.iter().filter_map(|p| Some((p.name, p.statistics?))).collect();
    }

    /// The `q`-quantile (0..=1) of the kept frames' GPU time, nearest rank.
    pub fn gpu_percentile(&self, q: f64) -> Option<f64> {
        let mut ms: Vec<f64> = self.samples.iter().map(|s| s.gpu_ms).collect();
        ms.sort_by(f64::total_cmp);
        let last = ms.len().checked_sub(1)?;
        Some(ms[((q * last as f64).round() as usize).min(last)])
    }

    /// The panel: graph, legend with each pass's mean, percentiles, CPU times, cull counts.
    pub fn show(&self, ui: &mut Ui) {
        if !self.gpu_available {
            ui.label("GPU times unavailable: the queue writes no timestamps");
        } else if self.samples.is_empty() {
            ui.label("no frame measured yet");
            return;
        } else {
            self.graph(ui);
            self.legend(ui);
            let p = |q| self.gpu_percentile(q).unwrap_or(0.0);
            ui.label(format!(
                "GPU frame over {} frames: p50 {:.2}  p95 {:.2}  p99 {:.2} ms",
                self.samples.len(),
                p(0.5),
                p(0.95),
                p(0.99)
            ));
        }
        let n = self.samples.len().max(1) as f64;
        let cpu = |i: usize| self.samples.iter().map(|s| s.cpu[i]).sum::<f64>() / n;
        ui.label(format!("CPU per frame: record {:.3}  submit {:.3}  wait {:.2} ms", cpu(0), cpu(1), cpu(2)));
        match &self.cull {
            Some(c) => ui.label(format!("cull: {}", c.summary())),
            None => ui.label("cull: off (brute force)"),
        };
        self.statistics_grid(ui);
    }

    /// The last frame's pipeline statistics of each counted graphics pass.
    fn statistics_grid(&self, ui: &mut Ui) {
        if self.statistics.is_empty() {
            ui.label("pipeline statistics: none (no pipelineStatisticsQuery, or --no-ui)");
            return;
        }
        egui::Grid::new("statistics").striped(true).show(ui, |ui| {
            for heading in ["pass", "vertices", "VS", "clipped prims", "FS"] {
                ui.label(heading);
            }
            ui.end_row();
            for (name, s) in &self.statistics {
                ui.label(*name);
                for n in [s.input_vertices, s.vertex_invocations, s.clipping_primitives, s.fragment_invocations] {
                    ui.label(n.to_string());
                }
                ui.end_row();
            }
        });
    }

    /// Stacked bars, one column per frame (oldest left), one colour per pass.
    fn graph(&self, ui: &mut Ui) {
        let (rect, _) = ui.allocate_exact_size(Vec2::new(ui.available_width().max(200.0), 90.0), Sense::hover());
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 2.0, Color32::from_black_alpha(160));
        let top = self.samples.iter().map(|s| s.gpu_ms).fold(1.0, f64::max) * 1.1;
        let column = rect.width() / HISTORY as f32;
        let scale = rect.height() as f64 / top;
        for (i, sample) in self.samples.iter().enumerate() {
            let x = rect.left() + column * (HISTORY - self.samples.len() + i) as f32;
            let mut y = rect.bottom();
            for (name, ms) in &sample.passes {
                let h = (ms * scale) as f32;
                let bar = Rect::from_min_max(egui::pos2(x, y - h), egui::pos2(x + column.max(1.0), y));
                painter.rect_filled(bar, 0.0, self.color(name));
                y -= h;
            }
        }
        painter.text(
            rect.left_top() + Vec2::new(4.0, 2.0),
            egui::Align2::LEFT_TOP,
            format!("{top:.1} ms"),
            egui::FontId::monospace(10.0),
            Color32::WHITE,
        );
        painter.rect_stroke(rect, 2.0, Stroke::new(1.0, Color32::GRAY), egui::StrokeKind::Inside);
    }

    /// Each pass's colour and mean GPU time.
    fn legend(&self, ui: &mut Ui) {
        let n = self.samples.len().max(1) as f64;
        ui.horizontal_wrapped(|ui| {
            for name in &self.names {
                let mean = self
                    .samples
                    .iter()
                    .flat_map(|s| &s.passes)
                    .filter(|(p, _)| p == name)
                    .map(|(_, ms)| ms)
                    .sum::<f64>()
                    / n;
                ui.colored_label(self.color(name), format!("■ {name} {mean:.2}"));
            }
        });
    }

    fn color(&self, name: &str) -> Color32 {
        const PALETTE: [Color32; 10] = [
            Color32::from_rgb(86, 180, 233),
            Color32::from_rgb(230, 159, 0),
            Color32::from_rgb(0, 158, 115),
            Color32::from_rgb(240, 228, 66),
            Color32::from_rgb(0, 114, 178),
            Color32::from_rgb(213, 94, 0),
            Color32::from_rgb(204, 121, 167),
            Color32::from_rgb(160, 160, 160),
            Color32::from_rgb(120, 200, 120),
            Color32::from_rgb(200, 80, 80),
        ];
        let i = self.names.iter().position(|n| *n == name).unwrap_or(0);
        PALETTE[i % PALETTE.len()]
    }
}
