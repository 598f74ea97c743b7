//! What a pass declares for a frame: its kind (compute, or graphics with the rendering instance the
//! graph opens), and its steps, each with the resources it touches and how. The graph derives the
//! barriers before each step from them (`vk::tracker`, `vk::sync`).

use ash::vk;
use smallvec::{smallvec, SmallVec};

use crate::render::graph::Temporal;
use crate::vk::tracker::Accesses;
use crate::vk::{Access, Resource};

/// How an attachment's contents start.
#[derive(Clone, Copy)]
pub enum Load {
    /// Cleared to a value.
    Clear(vk::ClearValue),
    /// Kept from the previous pass.
    Keep,
    /// Undefined: the pass writes every pixel (or does not use the contents).
    Discard,
}

/// One attachment of a graphics pass.
#[derive(Clone, Copy)]
pub struct Attachment {
    /// The image (tracked as a resource).
    pub image: vk::Image,
    /// The view drawn into.
    pub view: vk::ImageView,
    /// How its contents start.
    pub load: Load,
    /// Whether its contents are stored for a later pass (depth a later pass does not read is not).
    pub store: bool,
}

/// The rendering instance of a graphics pass.
#[derive(Clone, Copy)]
pub struct Rendering {
    /// Render area, from the origin.
    pub extent: vk::Extent2D,
    /// Colour attachment.
    pub color: Option<Attachment>,
    /// Depth attachment (reversed Z).
    pub depth: Option<Attachment>,
    /// Whether the pass's pipelines write depth (`pipeline::GraphicsDesc::depth_write`). A pass
    /// that only tests depth (blended far plants, decals) reads it (`Access::DepthAttachmentRead`):
    /// passes that only test follow each other with no barrier between them.
    pub depth_write: bool,
    /// The pass's first pipeline. Bound before its statistics query begins: lavapipe (Mesa 22.3)
    /// emits the bound graphics state at `vkCmdBeginQuery` and crashes when there is none.
    pub pipeline: vk::Pipeline,
    /// The draws come from secondary command buffers. Such a pass goes uncounted by the
    /// statistics queries (that would need `inheritedQueries`).
    pub secondary: bool,
}

/// What kind of work a pass records.
pub enum Kind {
    /// Dispatches, outside any rendering instance.
    Compute,
    /// Draws inside a rendering instance the graph opens.
    Graphics(Rendering),
}

/// A use of a resource: a tracked resource itself, or one side of a temporal pair (resolved by
/// the graph to this frame's resource).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Use {
    /// A buffer or image.
    Resource(Resource),
    /// The resource of the pair written this frame.
    Current(Temporal),
    /// The resource of the pair the last submitted frame wrote.
    Previous(Temporal),
}

/// A step's uses grouped by resource (`Declaration::grouped`), inline: a frame's plan allocates
/// little (its record is measured against 0.1 ms of CPU).
pub(super) type Groups = SmallVec<[(Resource, Accesses); 8]>;

/// One step of a pass: the commands `Pass::record` records when `PassContext::step` is its index,
/// after the barriers its uses need.
pub struct Step {
    /// Its name in the frame's step timings (`FrameTimings::steps`), or `None`: not measured apart
    /// from the pass.
    pub name: Option<&'static str>,
    /// `(resource, access)` uses, attachments excluded (the graph adds those to the first step).
    pub uses: SmallVec<[(Use, Access); 8]>,
}

/// What a pass does this frame: its kind, and its steps with every resource each touches.
pub struct Declaration {
    /// Compute or graphics.
    pub kind: Kind,
    /// The steps, in order; at least one. A graphics pass has one.
    pub steps: SmallVec<[Step; 1]>,
}

impl Declaration {
    /// A compute pass.
    pub fn compute() -> Self {
        Self { kind: Kind::Compute, steps: smallvec![Step { name: None, uses: SmallVec::new() }] }
    }

    /// A graphics pass with its rendering instance.
    pub fn graphics(rendering: Rendering) -> Self {
        Self { kind: Kind::Graphics(rendering), steps: smallvec![Step { name: None, uses: SmallVec::new() }] }
    }

    /// Start step `name` (measured by its own timestamps): the uses declared next are its own, and
    /// the graph records the barriers they need after the steps before it (a dispatch that reads
    /// what the previous dispatch wrote). Named first, it names the first step.
    pub fn step(mut self, name: &'static str) -> Self {
        match self.steps.as_mut_slice() {
            [only] if only.name.is_none() && only.uses.is_empty() => only.name = Some(name),
            _ => self.steps.push(Step { name: Some(name), uses: SmallVec::new() }),
        }
        self
    }

    /// Start a step that is not measured apart from its pass (one iteration of a solver's many):
    /// as `step`, without its timestamps. First, it is the first step.
    pub fn then(mut self) -> Self {
        match self.steps.as_mut_slice() {
            [only] if only.name.is_none() && only.uses.is_empty() => {}
            _ => self.steps.push(Step { name: None, uses: SmallVec::new() }),
        }
        self
    }

    /// The current step uses `resource` as `access`.
    pub fn uses(self, resource: Resource, access: Access) -> Self {
        self.uses_of(Use::Resource(resource), access)
    }

    /// The current step uses buffer `buffer` as `access`.
    pub fn buffer(self, buffer: vk::Buffer, access: Access) -> Self {
        self.uses(Resource::Buffer(buffer), access)
    }

    /// The current step uses the whole single-mip colour image `image` (2-D, or 3-D: a storage
    /// grid) as `access`.
    pub fn image(self, image: vk::Image, access: Access) -> Self {
        self.uses(Resource::color(image), access)
    }

    /// The current step uses this frame's resource of `pair` (the one written this frame) as
    /// `access`. A frame that writes it swaps the pair once it is submitted.
    pub fn current(self, pair: Temporal, access: Access) -> Self {
        self.uses_of(Use::Current(pair), access)
    }

    /// The current step uses the resource of `pair` that the last submitted frame wrote.
    pub fn previous(self, pair: Temporal, access: Access) -> Self {
        self.uses_of(Use::Previous(pair), access)
    }

    fn uses_of(mut self, resource: Use, access: Access) -> Self {
        self.steps.last_mut().expect("a declaration has a step").uses.push((resource, access));
        self
    }

    /// Every use of step `step` grouped by resource, in order of first appearance, the
    /// attachments included in the first step; `resolve` gives a temporal use's resource.
    pub(super) fn grouped(&self, step: usize, resolve: impl Fn(Use) -> Resource) -> Groups {
        let mut groups = Groups::new();
        let mut add = |resource: Resource, access: Access| match groups.iter_mut().find(|(r, _)| *r == resource) {
            Some((_, accesses)) => accesses.push(access),
            None => groups.push((resource, smallvec![access])),
        };
        if let (0, Kind::Graphics(rendering)) = (step, &self.kind) {
            if let Some(color) = rendering.color {
                add(Resource::color(color.image), Access::ColorAttachmentWrite);
            }
            if let Some(depth) = rendering.depth {
                let access =
                    if rendering.depth_write { Access::DepthAttachmentReadWrite } else { Access::DepthAttachmentRead };
                add(Resource::depth(depth.image), access);
            }
        }
        for &(resource, access) in &self.steps[step].uses {
            add(resolve(resource), access);
        }
        groups
    }

    /// The temporal pairs whose current resource a step of this frame writes.
    pub(super) fn writes_current(&self) -> impl Iterator<Item = Temporal> + '_ {
        self.steps.iter().flat_map(|s| &s.uses).filter_map(|&(resource, access)| match resource {
            Use::Current(pair) if access.writes() != vk::AccessFlags2::NONE => Some(pair),
            _ => None,
        })
    }

    /// Whether a use names a temporal pair (its commands depend on the pair's parity).
    pub(super) fn is_temporal(&self) -> bool {
        self.steps.iter().flat_map(|s| &s.uses).any(|(resource, _)| !matches!(resource, Use::Resource(_)))
    }

    /// The steps measured apart (named).
    pub(super) fn timed_steps(&self) -> u32 {
        self.steps.iter().filter(|s| s.name.is_some()).count() as u32
    }
}
