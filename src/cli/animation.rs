//! The animation flags shared by `render`, `view` and `timing` (mode, keyframes, wind, sources,
//! calm areas, colliders) and their conversion into [`AnimationSettings`].

use clap::{Args, ValueEnum};

use crate::app::values;
use crate::harness::bench::Column;
use crate::keyframes::encoding::{Encoding, Packing};
use crate::keyframes::{Representation, Smoothing};
use crate::render::animation::{AnimationSettings, Eval, Mode};
use crate::wind::{Attenuation, GlobalWind, Wind};

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum ModeArg {
    /// Neutral blades, no forces.
    Static,
    /// Keyframes sampled from a texture in the vertex shader (thesis 4.4.1).
    Texture,
    /// Keyframes in a uniform array, two 16-bit values per word (thesis 4.4.2).
    Uniform,
    /// Benchmark floor: pre-expanded static triangles, flat colour.
    Floor,
}

/// The blade response (`render::animation::response`).
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum AnimationArg {
    /// Neutral blades, no forces (as --mode static).
    Static,
    /// The thesis' keyframes: --mode texture or uniform, --eval, and the keyframe flags.
    Keyframes,
    /// Pelzer's sine (GPU Gems ch. 7, §7.4.4): one phase per blade, at its root.
    SineObject,
    /// Pelzer's sine (§7.4.3): a phase per vertex of the blade's backbone, from its world position.
    SineVertex,
    /// Pelzer's sine (§7.4.2): one phase per tile of the cull, drawn as one draw per visible tile.
    SineCluster,
    /// Zhang Xia's Verlet blades (§3.2.3–3.2.5): control points with state, --stiffness and --damping.
    Verlet,
    /// Belyaev's inertial blades (§3.1): segment chains with state, --stiffness and --damping.
    Inertial,
    /// Belyaev's virtually-inertial blades (§3.3): chains at the wind's corners, drawn blades at equilibrium.
    VirtualInertial,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum PackingArg {
    /// The thesis' merge/extract in a 32-bit float.
    Thesis,
    /// Two snorm16 in a uint (exact).
    Snorm,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum RepresentationArg {
    /// One record per vertex pair (the thesis).
    Vertex,
    /// Three displaced Bézier control points per pose, any segment count.
    Curve,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum EvalArg {
    /// Once per drawn blade with the cull, per vertex with --brute-force.
    Auto,
    /// Per vertex in the vertex shader.
    Vertex,
    /// Once per blade in a compute pass that evaluates every level.
    Blade,
}

#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum DebugViewArg {
    /// Force magnitude as colour, green (none) to red (strongest pose).
    Force,
    /// The force clusters' edges over the picture, coloured by the force at each corner.
    Bounds,
    /// The wind field the grass feels, as arrows on a slice 0.5 m above the ground, coloured by speed: blue (calm), cyan, yellow, red (8 m/s and more).
    Wind,
    /// Blades coloured by LOD bucket: red 1 segment, orange 2, yellow 4, green 8, blue 16.
    Lod,
    /// Blades coloured by the cull's tile they belong to.
    Tiles,
    /// Blades show Belyaev's Fresnel term alone (§2.3), unfogged: bright where the terrain is seen edge-on.
    Fresnel,
    /// The ground's cover (--cover, --slope-limit) as colour on the terrain and the blades: red bare, yellow half, green full.
    Cover,
    /// The pressed map on the blades: green untouched, to magenta where trampled or freshly cut (how far from its own pose the map takes a blade).
    Pressed,
    /// The interaction patches on the blades: grey-green drawn by the response, to orange where a collider's patch draws a blade by its inertial chain (Belyaev §3.4).
    Patches,
    /// The far field apart from the blades: blades blue-green, those in the band where they thin out orange, the far field's plants magenta (render::far_field).
    Far,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum SmoothingArg {
    Nearest,
    Linear,
    Slerp,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum EncodingArg {
    Rgba8x2,
    Unorm16,
    Float32,
}

/// The wind field (`render::wind`).
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
pub(crate) enum WindFieldArg {
    /// The thesis' global wind with gusts, point sources and calm areas.
    Analytic,
    /// Belyaev's wind (§3.2): three scrolling layers of a noise texture in place of the global
    /// wind and its gusts; sources and calm areas as analytic.
    Perlin,
    /// Zhang Xia's stable fluid (§2): a 3-D velocity grid around the camera, stepped on the GPU,
    /// the analytic field past it.
    Fluid,
}

#[derive(Clone, Copy, ValueEnum)]
pub(crate) enum AttenuationArg {
    Cluster,
    Blade,
}

#[derive(Args)]
pub(crate) struct AnimationArgs {
    /// The blade response: what poses the blades under the wind.
    #[arg(long, value_enum, default_value = "keyframes")]
    pub(crate) animation: AnimationArg,
    /// Keyframe table (texture or uniform array), static blades, or the benchmark floor.
    #[arg(long, value_enum, default_value = "texture")]
    pub(crate) mode: ModeArg,
    /// Keyframe poses over the full circle (a quarter is stored).
    #[arg(long, default_value = "1000", value_parser = values::poses)]
    pub(crate) poses: u32,
    /// In-between poses (thesis 3.2.6).
    #[arg(long, value_enum, default_value = "nearest")]
    pub(crate) smoothing: SmoothingArg,
    /// Keyframe texture encoding (thesis 4.4.1).
    #[arg(long, value_enum, default_value = "unorm16")]
    pub(crate) encoding: EncodingArg,
    /// Uniform-array packing of two 16-bit values per word (thesis 4.4.2).
    #[arg(long, value_enum, default_value = "snorm")]
    pub(crate) packing: PackingArg,
    /// Keyframe representation: per vertex pair (thesis) or Bézier control points.
    #[arg(long, value_enum, default_value = "vertex")]
    pub(crate) keyframes: RepresentationArg,
    /// Where the per-blade part of the animation runs: every vertex, or once per blade (compute);
    /// `auto`: once per drawn blade with the cull, every vertex with --brute-force (the thesis).
    #[arg(long, value_enum, default_value = "auto")]
    pub(crate) eval: EvalArg,
    /// Where point sources are attenuated (thesis 4.5): at cluster corners or per blade.
    #[arg(long, value_enum, default_value = "cluster")]
    pub(crate) attenuation: AttenuationArg,
    /// Cluster edge in metres (thesis 3.2.2).
    #[arg(long, default_value = "1.0", value_parser = values::cluster_size)]
    pub(crate) cluster_size: f32,
    /// Global wind: direction it blows towards (degrees from +x towards +z) and strength.
    #[arg(long, value_name = "DIR_DEG,STRENGTH", default_value = "30,0.3", value_parser = values::wind, allow_hyphen_values = true)]
    pub(crate) wind: (f32, f32),
    /// Steady global wind, without gusts.
    #[arg(long)]
    pub(crate) no_gusts: bool,
    /// The wind field that carries the wind to the blades.
    #[arg(long, value_enum, default_value = "analytic")]
    pub(crate) wind_field: WindFieldArg,
    /// The fluid wind's cells per axis (x, y up, z).
    #[arg(long, value_name = "NX,NY,NZ", default_value = "32,16,32", value_parser = values::fluid_grid)]
    pub(crate) fluid_grid: [u32; 3],
    /// The fluid wind's cell width (x and z) and height, in metres.
    #[arg(long, value_name = "DXZ,DY", default_value = "1,0.5", value_parser = values::fluid_cell, allow_hyphen_values = true)]
    pub(crate) fluid_cell: [f32; 2],
    /// Point wind source (eq. 4.1), optionally moving, at a height above the ground (where the
    /// fluid wind injects it; 0.5 m by default); repeatable.
    #[arg(long, value_name = "X,Z,POWER,SIGMA[,VX,VZ][,HEIGHT]", value_parser = values::source, allow_hyphen_values = true)]
    pub(crate) source: Vec<crate::wind::PointSource>,
    /// Calm area where the wind is blocked (thesis 5.1); repeatable.
    #[arg(long, value_name = "X0,Z0,X1,Z1", value_parser = values::calm, allow_hyphen_values = true)]
    pub(crate) calm: Vec<crate::wind::CalmArea>,
    /// Collider pushing aside the part of each blade inside it (thesis 5.2 in 3-D; Y is a world height) and the blades out of it (Zhang Xia §6.2): sphere:X,Y,Z,R[,VX,VY,VZ] or ellipsoid:X,Y,Z,RX,RY,RZ[,VX,VY,VZ], moving at (VX, VY, VZ) m/s; repeatable.
    #[arg(long, value_name = "SHAPE", value_parser = values::collider, allow_hyphen_values = true)]
    pub(crate) collider: Vec<crate::wind::Collider>,
    /// Cutter: a sphere or ellipsoid (the shapes of --collider, optionally moving) that cuts the blades it sweeps to a stub, which regrow over --regrow-s; repeatable.
    #[arg(long, value_name = "SHAPE", value_parser = values::collider, allow_hyphen_values = true)]
    pub(crate) cut: Vec<crate::wind::Collider>,
    /// Seconds a trampled blade takes to come back to 5 % of its pressed displacement (a critically damped spring).
    #[arg(long, value_name = "SECONDS", default_value = "20", value_parser = values::positive_f32, allow_hyphen_values = true)]
    pub(crate) recovery_s: f32,
    /// Seconds a cut blade takes to regrow to its full length.
    #[arg(long, value_name = "SECONDS", default_value = "30", value_parser = values::positive_f32, allow_hyphen_values = true)]
    pub(crate) regrow_s: f32,
    /// Simulation time of the picture in seconds.
    #[arg(long, default_value = "0", value_parser = values::time, allow_hyphen_values = true)]
    pub(crate) time: f32,
    /// The simulation's fixed time step in seconds, a number or a fraction (at most 1/15): headless
    /// frames lie one step apart, the viewer runs at most 4 steps a frame.
    #[arg(long, value_name = "SECONDS", default_value = "1/60", value_parser = values::dt, allow_hyphen_values = true)]
    pub(crate) dt: f64,
    /// The spring towards the rest shape, in 1/s² (1 to 400): the Verlet blades' k_s, whose
    /// natural period is about 2π/√k_s, or the inertial chains' joint stiffness k/J, whose period
    /// is 2π/√(k/J).
    #[arg(long, default_value = "100", value_parser = values::stiffness, allow_hyphen_values = true)]
    pub(crate) stiffness: f32,
    /// The damping, in 1/s (0 to 20): the Verlet blades' drag rate towards the wind k_a (the wind
    /// moves a control point by k_a / k_s times its velocity at rest), or the inertial chains'
    /// joint damper d/J.
    #[arg(long, default_value = "4", value_parser = values::damping, allow_hyphen_values = true)]
    pub(crate) damping: f32,
}

impl AnimationArgs {
    /// The settings; `culled`: whether the cull runs (it decides `--eval auto`).
    pub(crate) fn settings(&self, culled: bool) -> AnimationSettings {
        AnimationSettings {
            mode: self.animation.mode(self.mode),
            packing: match self.packing {
                PackingArg::Thesis => Packing::Thesis,
                PackingArg::Snorm => Packing::Snorm,
            },
            representation: match self.keyframes {
                RepresentationArg::Vertex => Representation::Vertex,
                RepresentationArg::Curve => Representation::Curve,
            },
            eval: self.eval.resolve(culled),
            poses: self.poses,
            smoothing: match self.smoothing {
                SmoothingArg::Nearest => Smoothing::Nearest,
                SmoothingArg::Linear => Smoothing::Linear,
                SmoothingArg::Slerp => Smoothing::Slerp,
            },
            encoding: match self.encoding {
                EncodingArg::Rgba8x2 => Encoding::Rgba8x2,
                EncodingArg::Unorm16 => Encoding::Unorm16,
                EncodingArg::Float32 => Encoding::Float32,
            },
            attenuation: match self.attenuation {
                AttenuationArg::Cluster => Attenuation::Cluster,
                AttenuationArg::Blade => Attenuation::Blade,
            },
            cluster_size: self.cluster_size,
            wind: Wind {
                global: Some(GlobalWind { direction_deg: self.wind.0, strength: self.wind.1, gusts: !self.no_gusts }),
                sources: self.source.clone(),
                calm: self.calm.clone(),
                colliders: self.collider.clone(),
                cuts: self.cut.clone(),
            },
            wind_field: self.wind_field.kind(),
            fluid: crate::wind::FluidGrid { dims: self.fluid_grid, cell: self.fluid_cell },
            clock: crate::render::animation::clock::StepClock { dt: self.dt },
            verlet: crate::render::animation::verlet::VerletParams { stiffness: self.stiffness, damping: self.damping },
            chain: crate::render::animation::chain::ChainParams { stiffness: self.stiffness, damping: self.damping },
            pressed: crate::render::animation::pressed::PressedParams {
                recovery_s: self.recovery_s,
                regrow_s: self.regrow_s,
            },
        }
    }
}

impl WindFieldArg {
    /// The field.
    pub(crate) fn kind(self) -> crate::render::wind::FieldKind {
        match self {
            WindFieldArg::Analytic => crate::render::wind::FieldKind::Analytic,
            WindFieldArg::Perlin => crate::render::wind::FieldKind::Perlin,
            WindFieldArg::Fluid => crate::render::wind::FieldKind::Fluid,
        }
    }
}

impl AnimationArg {
    /// The mode: for keyframes, the one `--mode` names.
    pub(crate) fn mode(self, mode: ModeArg) -> Mode {
        use crate::render::animation::sine::SinePhase;
        match self {
            AnimationArg::Static => Mode::Static,
            AnimationArg::Keyframes => mode.animation(),
            AnimationArg::SineObject => Mode::Sine(SinePhase::Object),
            AnimationArg::SineVertex => Mode::Sine(SinePhase::Vertex),
            AnimationArg::SineCluster => Mode::Sine(SinePhase::Cluster),
            AnimationArg::Verlet => Mode::Verlet,
            AnimationArg::Inertial => Mode::Inertial,
            AnimationArg::VirtualInertial => Mode::VirtualInertial,
        }
    }
}

impl ModeArg {
    /// The animation mode; the floor draws the static blades' triangles.
    pub(crate) fn animation(self) -> Mode {
        match self {
            ModeArg::Static | ModeArg::Floor => Mode::Static,
            ModeArg::Texture => Mode::Texture,
            ModeArg::Uniform => Mode::Uniform,
        }
    }

    /// Whether this is the floor reference pass.
    pub(crate) fn is_floor(self) -> bool {
        matches!(self, ModeArg::Floor)
    }
}

impl From<ModeArg> for Column {
    fn from(mode: ModeArg) -> Self {
        match mode {
            ModeArg::Floor => Column::Floor,
            other => Column::Animated(other.animation()),
        }
    }
}

impl EvalArg {
    /// The placement; `auto` is `Eval::default_for` the cull.
    pub(crate) fn resolve(self, culled: bool) -> Eval {
        match self {
            EvalArg::Auto => Eval::default_for(culled),
            EvalArg::Vertex => Eval::Vertex,
            EvalArg::Blade => Eval::Blade,
        }
    }
}
