//! The pass graph: an ordered list of passes, compute or graphics, each declaring the resources it
//! reads and writes as `vk::sync::Access` values. The graph owns everything between the passes:
//!
//! - **barriers**: it tracks each resource's last access across passes and frames
//!   (`vk::tracker`) and derives every barrier through `vk::sync::transition`, image layouts,
//!   swapchain acquire and present included, and between the steps of a pass (a chain of
//!   dependent dispatches, `Declaration::step`);
//! - **time**: the frame clock (`FrameClock`), and temporal pairs (`Temporal`: ping-pong
//!   resources declared once, swapped when a frame that wrote them is submitted);
//! - **when a pass runs**: every frame, or once and again when its inputs change (`Runs`);
//! - **rendering instances**: a graphics pass names its attachments and how they load; the graph
//!   begins and ends the dynamic-rendering instance around the pass's draws;
//! - **GPU scopes**: a debug label, a timestamp pair (and one per named step) and, for graphics
//!   passes, a pipeline-statistics query around each pass, so every report lists every pass with
//!   no per-pass code. The frame's queries are sized from its plan: any number of passes;
//! - **replays**: whether a kept recording still holds for this frame (`Plan::replay`);
//! - **outputs**: the frame's last uses of its target (present, a copy for the host to read).
//!
//! A pass records only its own commands: adding a pass is one file that implements [`Pass`] and
//! one `graph.add(…)` line (or `Renderer::add_pass` from outside the library).

mod declaration;
mod destroy;
mod recording;
mod temporal;
mod uniforms;

pub use declaration::{Attachment, Declaration, Kind, Load, Rendering, Step, Use};
pub use temporal::{FrameClock, Temporal, TemporalPair, DEFAULT_DT};
pub use uniforms::PassUniforms;

use ash::vk;

use crate::error::{Error, Result};
use crate::render::target::TargetView;
use crate::render::uniforms::FrameUniforms;
use crate::vk::query::{StatisticsQueries, TimestampQueries};
use crate::vk::tracker::{Barriers, Resource, ResourceStates};
use crate::vk::{image, sync, Access, Device};
use recording::{record_pass, StepStates};

/// What a frame's passes are recorded for.
#[derive(Clone, Copy)]
pub struct PassContext<'a> {
    /// The device.
    pub device: &'a Device,
    /// The colour and depth images the scene passes draw into: the frame's target, or with
    /// `--msaa` the multisampled pair the resolve pass reads (`render::msaa`).
    pub target: &'a TargetView,
    /// The frame's target: what is read back or presented after the passes.
    pub output: &'a TargetView,
    /// The frame in flight being recorded (indexes per-frame resources a pass owns).
    pub slot: usize,
    /// The frame's descriptor set 0 (scene, per-frame uniforms and forces).
    pub descriptor_set: vk::DescriptorSet,
    /// The frame's uniforms as written for the GPU (what a pass sizes its dispatches by).
    pub uniforms: &'a FrameUniforms,
    /// The frame's clock: its `time` and `dt` from the caller, its `index` from the graph.
    pub clock: FrameClock,
    /// The step being recorded (`Declaration::step`; 0 for a pass of one step). Set by the graph.
    pub step: usize,
    /// The graph's temporal pairs as they stand this frame. Set by the graph.
    pub temporals: &'a [TemporalPair],
}

impl PassContext<'_> {
    /// `pair` as it stands this frame.
    pub fn temporal(&self, pair: Temporal) -> TemporalPair {
        self.temporals[pair.0]
    }

    /// The resource of `pair` written this frame.
    pub fn current(&self, pair: Temporal) -> Resource {
        self.temporal(pair).current()
    }

    /// The resource of `pair` the last submitted frame wrote.
    pub fn previous(&self, pair: Temporal) -> Resource {
        self.temporal(pair).previous()
    }

    /// The resource a use names this frame.
    fn resolve(&self, resource: Use) -> Resource {
        match resource {
            Use::Resource(resource) => resource,
            Use::Current(pair) => self.current(pair),
            Use::Previous(pair) => self.previous(pair),
        }
    }
}

/// When a pass runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Runs {
    /// Every frame (it may still skip a frame by declaring nothing).
    EveryFrame,
    /// Once, and again when the key changes: the key is a digest of every input the pass's
    /// output depends on (an atlas bake: the blade look). A run counts once its frame is
    /// submitted; a dropped frame's run is run again.
    OnChange(u64),
}

/// A pass of the graph: one file, its own pipelines, its declaration, its commands.
pub trait Pass {
    /// Name in debug labels, timings and reports.
    fn name(&self) -> &'static str;

    /// What the pass does this frame, or `None` to skip it this frame.
    fn declare(&self, ctx: &PassContext) -> Option<Declaration>;

    /// Record the pass's commands for step `ctx.step` of its declaration: binds and dispatches
    /// or draws. Barriers (before each step), the rendering instance, labels and queries are the
    /// graph's. Set 0 is not bound by the graph.
    fn record(&self, ctx: &PassContext, cmd: vk::CommandBuffer) -> Result<()>;

    /// The pass's own uniform block (`PassUniforms`, one per frame in flight, bound in the pass's
    /// own set) and its contents this frame: the graph writes them into the frame's block before
    /// the frame is submitted, on each frame the pass runs (replayed or recorded). `None` by
    /// default.
    fn uniforms(&self, _ctx: &PassContext) -> Option<(&PassUniforms, Vec<u8>)> {
        None
    }

    /// When the pass runs: every frame by default.
    fn runs(&self, _ctx: &PassContext) -> Runs {
        Runs::EveryFrame
    }

    /// What this frame's commands of the pass are a function of, besides the resources and the
    /// target a replay is already checked against: `Some(key)` when the commands recorded for an
    /// earlier frame with the same key are this frame's too (a `Prerecorded` replay may reuse
    /// them), `None` when they must be recorded anew. `None` by default: a pass that decides
    /// on the CPU what to draw (a per-frame draw list, culled chunks), writes per-frame data in
    /// `record`, or keeps state of its own, is never replayed stale. Passes that use a temporal
    /// pair or run on change are recorded anew whatever they say.
    fn replay_key(&self, _ctx: &PassContext) -> Option<u64> {
        None
    }

    /// The frame last recorded will not run (it failed to record or submit): forget anything the
    /// pass assumed that frame's commands would leave behind (`ReliefGridPass` keeps what its
    /// last dispatch computed). Nothing to forget by default.
    fn frame_dropped(&self) {}

    /// Destroy the pass's pipelines and resources.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    unsafe fn destroy(self: Box<Self>, device: &Device);
}

/// The queries a frame's passes are measured with. Their pools must hold what the frame's plan
/// needs (`Plan::timestamps`, `Plan::statistics`).
pub struct Scopes<'a> {
    /// Timestamps: two per pass and per named step, and one at each end of the frame.
    pub timestamps: &'a mut TimestampQueries,
    /// Pipeline statistics, one query per counted graphics pass, when available.
    pub statistics: Option<&'a mut StatisticsQueries>,
}

/// A named step of a pass as recorded: which timestamps measured it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RecordedStep {
    /// The step's name.
    pub name: &'static str,
    /// Timestamp written before the step (before its barriers).
    pub begin: u32,
    /// Timestamp written after it.
    pub end: u32,
}

/// A pass as recorded in a frame: which queries measured it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RecordedPass {
    /// The pass's name.
    pub name: &'static str,
    /// Timestamp written before the pass (before its barriers).
    pub begin: u32,
    /// Timestamp written after the pass.
    pub end: u32,
    /// Its pipeline-statistics query, if counted.
    pub statistics: Option<u32>,
    /// Its named steps.
    pub steps: Vec<RecordedStep>,
}

/// What the frame's target goes on to after the passes.
#[derive(Clone, Copy, Debug, Default)]
pub struct Outputs {
    /// Copy the colour image into this host-visible buffer (tightly packed, 4 bytes a texel).
    pub readback: Option<vk::Buffer>,
    /// Hand the colour image to the presentation engine.
    pub present: bool,
}

/// One pass in the graph.
struct Node {
    pass: Box<dyn Pass>,
    /// The key of its last submitted run (`Runs::OnChange`).
    ran: Option<u64>,
}

/// The passes a frame records, with their declarations: made by `Graph::plan`, recorded by
/// `Graph::record`.
pub struct Plan {
    /// `(node, declaration, run key)` of each pass that runs.
    entries: Vec<(usize, Declaration, Option<u64>)>,
    /// The frame's replay key: `None` when the frame must be recorded anew.
    replay: Option<Vec<u64>>,
}

impl Plan {
    /// Timestamps the frame writes at most.
    pub fn timestamps(&self) -> u32 {
        2 + self.entries.iter().map(|(_, d, _)| 2 + 2 * d.timed_steps()).sum::<u32>()
    }

    /// Pipeline-statistics queries the frame uses at most (one per graphics pass).
    pub fn statistics(&self) -> u32 {
        self.entries.iter().filter(|(_, d, _)| matches!(d.kind, Kind::Graphics(_))).count() as u32
    }

    /// What the frame's commands are a function of, besides the resource states and the target
    /// (`Pass::replay_key` of each pass, and which passes run): equal keys, equal commands.
    /// `None`: the frame must be recorded.
    pub fn replay(&self) -> Option<&[u64]> {
        self.replay.as_deref()
    }
}

/// The context the passes see: `ctx` with the graph's clock index and temporal pairs.
fn context<'a>(ctx: &PassContext<'a>, temporals: &'a [TemporalPair], frames: u64) -> PassContext<'a> {
    let clock = FrameClock { index: frames, ..ctx.clock };
    PassContext { clock, step: 0, temporals, ..*ctx }
}

/// Passes in order, the states of the resources they touch, the temporal pairs and the clock.
#[derive(Default)]
pub struct Graph {
    nodes: Vec<Node>,
    /// The first `extensions` nodes were added from outside the renderer (`add_extension`): a
    /// rebuilt graph keeps them (`adopt`).
    extensions: usize,
    states: ResourceStates,
    temporals: Vec<TemporalPair>,
    /// Frames submitted.
    frames: u64,
    /// What the last recorded frame changes once it is submitted.
    pending: Pending,
}

/// What a recorded frame changes once it is submitted: the pairs it wrote swap, the runs on
/// change it recorded count.
#[derive(Default)]
struct Pending {
    swaps: Vec<usize>,
    runs: Vec<(usize, u64)>,
}

/// What a rebuilt graph keeps from the one it replaces: the passes added from outside, the
/// temporal pairs and the clock.
pub struct Kept {
    nodes: Vec<Node>,
    temporals: Vec<TemporalPair>,
    frames: u64,
}

impl Graph {
    /// An empty graph.
    pub fn new() -> Self {
        Self::default()
    }

    /// Append a pass: passes run in the order they were added.
    pub fn add(&mut self, pass: impl Pass + 'static) {
        self.add_boxed(Box::new(pass));
    }

    /// Append a pass built elsewhere (a blade response's compute passes).
    pub fn add_boxed(&mut self, pass: Box<dyn Pass>) {
        self.nodes.push(Node { pass, ran: None });
    }

    /// Add a pass from outside the renderer's own (a simulation, a bake): it runs before them,
    /// after the extensions added before it, and a rebuilt graph keeps it (`keep`, `adopt`).
    pub fn add_extension(&mut self, pass: Box<dyn Pass>) {
        self.nodes.insert(self.extensions, Node { pass, ran: None });
        self.extensions += 1;
    }

    /// Declare a temporal pair over `pair` (two resources of one shape). At first `pair[0]` is
    /// current: written by the first frame, and `pair[1]` is previous.
    pub fn temporal(&mut self, pair: [Resource; 2]) -> Temporal {
        self.temporals.push(TemporalPair { pair, current: 0 });
        Temporal(self.temporals.len() - 1)
    }

    /// `pair` as it stands (before the next frame).
    pub fn temporal_pair(&self, pair: Temporal) -> TemporalPair {
        self.temporals[pair.0]
    }

    /// Frames submitted so far: the next frame's `FrameClock::index`.
    pub fn frames_submitted(&self) -> u64 {
        self.frames
    }

    /// Take what a rebuilt graph keeps (the extensions, the temporal pairs, the clock).
    pub fn keep(&mut self) -> Kept {
        let nodes = self.nodes.drain(..self.extensions).collect();
        self.extensions = 0;
        Kept { nodes, temporals: std::mem::take(&mut self.temporals), frames: self.frames }
    }

    /// Take over what `kept` holds, before any pass of this graph is added.
    pub fn adopt(&mut self, kept: Kept) {
        self.extensions = kept.nodes.len();
        let own = std::mem::replace(&mut self.nodes, kept.nodes);
        self.nodes.extend(own);
        self.temporals = kept.temporals;
        self.frames = kept.frames;
    }

    /// The names of the passes, in order.
    pub fn pass_names(&self) -> Vec<&'static str> {
        self.nodes.iter().map(|n| n.pass.name()).collect()
    }

    /// `resource` was last accessed by `accesses` (uploaded data, a target's previous frame, an
    /// acquired swapchain image). Images must be imported before a pass uses them.
    pub fn import(&mut self, resource: Resource, accesses: &[Access]) {
        self.states.import(resource, accesses);
    }

    /// Forget `resource` (destroyed: its handle may be reused).
    pub fn forget(&mut self, resource: Resource) {
        self.states.forget(resource);
    }

    /// The resource states, e.g. to tell whether a recorded command buffer can be replayed (its
    /// barriers assumed the states it started from).
    pub fn states(&self) -> &ResourceStates {
        &self.states
    }

    /// Replace the resource states (after replaying a recording that ends in them).
    pub fn set_states(&mut self, states: ResourceStates) {
        self.states = states;
    }

    /// The frame last recorded (or replayed) was submitted: the temporal pairs it wrote swap, its
    /// runs on change count, and the clock moves on.
    pub fn frame_submitted(&mut self) {
        let pending = std::mem::take(&mut self.pending);
        for pair in pending.swaps {
            let t = &mut self.temporals[pair];
            t.current = 1 - t.current;
        }
        for (node, key) in pending.runs {
            self.nodes[node].ran = Some(key);
        }
        self.frames += 1;
    }

    /// The frame last recorded will not run: nothing it wrote swaps or counts, and each pass is
    /// told (`Pass::frame_dropped`).
    pub fn frame_dropped(&mut self) {
        self.pending = Pending::default();
        for node in &self.nodes {
            node.pass.frame_dropped();
        }
    }

    /// The passes that run this frame, with their declarations, and, when `keyed` (a frame that
    /// may replay a kept recording), the frame's replay key; the uniform blocks of the passes that
    /// run are written for the frame (`Pass::uniforms`). A graphics pass of several steps is
    /// refused.
    pub fn plan(&self, ctx: &PassContext, keyed: bool) -> Result<Plan> {
        let ctx = context(ctx, &self.temporals, self.frames);
        let mut entries = Vec::with_capacity(self.nodes.len());
        let mut replay = keyed.then(|| Vec::with_capacity(2 * self.nodes.len()));
        for (index, node) in self.nodes.iter().enumerate() {
            let pass = node.pass.as_ref();
            let run = match pass.runs(&ctx) {
                Runs::EveryFrame => None,
                Runs::OnChange(key) if node.ran == Some(key) => {
                    if let Some(keys) = replay.as_mut() {
                        keys.push(u64::MAX);
                    }
                    continue;
                }
                Runs::OnChange(key) => Some(key),
            };
            let Some(declaration) = pass.declare(&ctx) else {
                if let Some(keys) = replay.as_mut() {
                    keys.push(u64::MAX - 1);
                }
                continue;
            };
            if declaration.steps.len() > 1 && matches!(declaration.kind, Kind::Graphics(_)) {
                return Err(Error::Internal(format!("graphics pass `{}` declares several steps", pass.name())));
            }
            if let Some(keys) = &mut replay {
                let key = (run.is_none() && !declaration.is_temporal()).then(|| pass.replay_key(&ctx)).flatten();
                match key {
                    Some(key) => keys.extend([key, declaration.steps.len() as u64]),
                    None => replay = None,
                }
            }
            if let Some((block, bytes)) = pass.uniforms(&ctx) {
                block.write(ctx.slot, &bytes)?;
            }
            entries.push((index, declaration, run));
        }
        Ok(Plan { entries, replay })
    }

    /// Record the passes of `plan` into `cmd` with their barriers, rendering instance, label and
    /// queries, then the outputs. `ctx.target`'s images must have been imported for this frame.
    pub fn record(
        &mut self,
        ctx: &PassContext,
        plan: &Plan,
        cmd: vk::CommandBuffer,
        scopes: &mut Scopes,
        outputs: Outputs,
    ) -> Result<Vec<RecordedPass>> {
        let device = ctx.device;
        scopes.timestamps.reset(device, cmd);
        if let Some(statistics) = scopes.statistics.as_deref_mut() {
            statistics.reset(device, cmd);
        }
        scopes.timestamps.write(device, cmd);
        self.pending = Pending::default();
        let mut recorded = Vec::with_capacity(plan.entries.len());
        let mut pending = Pending::default();
        {
            let ctx = context(ctx, &self.temporals, self.frames);
            for (index, declaration, run) in &plan.entries {
                let pass = self.nodes[*index].pass.as_ref();
                let mut states = StepStates { states: &mut self.states, ctx: &ctx, name: pass.name(), declaration };
                recorded.push(record_pass(&ctx, cmd, scopes, pass, &mut states)?);
                pending.swaps.extend(declaration.writes_current().map(|t| t.0));
                if let Some(key) = run {
                    pending.runs.push((*index, *key));
                }
            }
        }
        pending.swaps.sort_unstable();
        pending.swaps.dedup();
        self.pending = pending;
        self.record_outputs(ctx, cmd, outputs);
        scopes.timestamps.write(device, cmd);
        Ok(recorded)
    }

    /// The target's last uses: a copy to the host (then host read), presentation.
    fn record_outputs(&mut self, ctx: &PassContext, cmd: vk::CommandBuffer, outputs: Outputs) {
        let device = ctx.device;
        let color = Resource::color(ctx.output.color);
        if let Some(raw) = outputs.readback {
            let buffer = Resource::Buffer(raw);
            self.release(device, cmd, &[(color, Access::TransferRead), (buffer, Access::TransferWrite)]);
            let extent = vk::Extent3D { width: ctx.output.extent.width, height: ctx.output.extent.height, depth: 1 };
            image::record_copy_to_buffer(device, cmd, ctx.output.color, extent, raw);
            self.release(device, cmd, &[(buffer, Access::HostRead)]);
        }
        if outputs.present {
            self.release(device, cmd, &[(color, Access::Present)]);
        }
    }

    /// Record the barriers that make `uses` safe after everything recorded so far (e.g. a host
    /// read of a buffer the frame wrote).
    pub fn release(&mut self, device: &Device, cmd: vk::CommandBuffer, uses: &[(Resource, Access)]) {
        let mut barriers = Barriers::default();
        for &(resource, access) in uses {
            if let Some(hazard) = self.states.access(resource, &[access]) {
                barriers.push(resource, &hazard);
            }
        }
        sync::cmd_barriers(device, cmd, &barriers.buffers, &barriers.images);
    }

    /// Destroy every pass.
    ///
    /// # Safety
    /// No pending GPU work may use them.
    pub unsafe fn destroy(self, device: &Device) {
        for node in self.nodes {
            // SAFETY: per the contract.
            unsafe { node.pass.destroy(device) };
        }
    }
}
