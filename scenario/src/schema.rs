//! The shape of a scenario file, as serde reads it: plain numbers in the
//! units `docs/scenarios.md` gives. Nothing here is checked beyond its
//! type; [`crate::check`] turns it into the core's types.

use serde::{Deserialize, Serialize};

/// A whole scenario file: who it is, and exactly one model table.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct File {
    /// The name in the stream header (1 to 32 bytes of `a-z 0-9 - _ .`).
    pub name: String,
    /// One line for `morphogen list`.
    #[serde(default)]
    pub summary: String,
    /// The seed used when `--seed` is not given.
    #[serde(default)]
    pub seed: u64,
    /// The seasonal growth curve.
    pub curve: Option<Curve>,
    /// A horn from positioners.
    pub horn: Option<Horn>,
    /// An L-system.
    pub lsystem: Option<LSystem>,
    /// A clonal mosaic (MClone).
    pub mosaic: Option<Mosaic>,
    /// A body grown by its table.
    pub body: Option<Body>,
    /// A bone: skeleton and shrinkwrap.
    pub bones: Option<Bones>,
}

/// A text or binary file the scenario names: a path relative to the
/// scenario file, or the text inline.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(untagged)]
pub enum Include {
    /// A path relative to the scenario file.
    Path(String),
    /// The file's text, inline.
    Inline {
        /// The text.
        text: String,
        /// Where the text came from, to name it in messages (`--set
        /// KEY=FILE` and `--grammar FILE` set it).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        name: Option<String>,
    },
}

/// The logistic growth curve f on `[0, span]` (days).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Sigmoid {
    /// c: the day of fastest growth.
    pub centre: f64,
    /// w: the logistic's time scale, days.
    pub width: f64,
    /// The life span, days (a horn's is its delay T and is not given).
    pub span: Option<f64>,
}

/// `[curve]`: f(t) sampled daily.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Curve {
    /// Days sampled after day 0.
    pub days: i64,
    /// The growth function.
    pub growth: Sigmoid,
}

/// One row of the horn paper's Table 1.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HornModule {
    /// Scale of the positioner's shape L_i(0), % of L_1(T).
    pub positioner_scale: f64,
    /// Scale of the lower base L_i(T), % of L_1(T).
    pub base_scale: f64,
    /// Bend α(T), degrees.
    pub bend: f64,
    /// Twist β(T), degrees.
    pub twist: f64,
    /// Radius of the path's arc, cm.
    pub path_radius: f64,
}

/// A horn's cross-section between a circle and an equilateral triangle.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Section {
    /// The circle's radius, cm (the triangle has the same area).
    pub radius: f64,
    /// 0: the circle; 1: the triangle, a corner up (+z); between: the
    /// polar radii blended.
    pub triangularity: f64,
}

/// `[horn]`: modules placed by positioners.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Horn {
    /// The delay T between modules, days.
    pub delay_days: i64,
    /// The growth of a module over its life T.
    pub growth: Sigmoid,
    /// Frames per year.
    pub frames_per_year: i64,
    /// Years shown (at most the number of modules).
    pub years: i64,
    /// Points per cross-section.
    pub ring_points: i64,
    /// Cross-sections per module.
    pub rings_per_module: i64,
    /// The cross-section L_1(T): a closed polyline of (y, z), cm; or
    /// instead `section`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub outline: Option<Vec<[f64; 2]>>,
    /// The cross-section L_1(T) from circular to triangular (horn paper,
    /// Secs. 2 and 8), instead of `outline`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<Section>,
    /// Table 1, tip first.
    pub modules: Vec<HornModule>,
}

/// `[lsystem]`: a grammar file (`docs/lsystems.md`) and any of its
/// settings and constants set from here.
#[derive(Debug, Clone, Deserialize, Serialize)]
pub struct LSystem {
    /// The grammar.
    pub grammar: Include,
    /// Every other key: a setting or constant of the grammar and its value
    /// (`delta = 30`), written into the grammar's text.
    #[serde(flatten)]
    pub constants: std::collections::BTreeMap<String, toml::Value>,
}

/// A mosaic's surface.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Domain {
    /// Extent along u and v.
    pub size: [f64; 2],
    /// Whether u and v wrap around.
    pub periodic: [bool; 2],
}

/// A cell type (thesis Table 3.1).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct CellType {
    /// A name for documents (F, B, M…).
    #[serde(default)]
    pub name: String,
    /// Display colour, RGB 0–255.
    pub colour: [i64; 3],
    /// D_T: mean days between divisions.
    pub division_days: i64,
    /// Probability that an initial cell is of this type.
    pub initial_probability: f64,
}

/// An anisotropy control vector.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ControlVector {
    /// Where, in domain coordinates.
    pub at: [f64; 2],
    /// The direction (|v| ≤ 1).
    pub v: [f64; 2],
}

/// The anisotropy field.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Anisotropy {
    /// w_a: the blend weight.
    pub weight: f64,
    /// σ of the inverse multiquadric.
    pub width: f64,
    /// The control vectors.
    pub vectors: Vec<ControlVector>,
}

/// Which days are frames.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(untagged)]
pub enum DayFrames {
    /// `"every-day"`.
    Keyword(String),
    /// These days.
    Days(Vec<i64>),
}

/// `[mosaic]`: MClone.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Mosaic {
    /// The surface.
    pub domain: Domain,
    /// C_i: initial cells.
    pub initial_cells: i64,
    /// Days after the initial relaxation.
    pub days: i64,
    /// w_r.
    pub radius_weight: f64,
    /// w_d.
    pub push_weight: f64,
    /// ρ_i.
    pub initial_relaxations: i64,
    /// ρ_s.
    pub daily_relaxations: i64,
    /// β of the heavy-ball relaxation (absent: 0, the thesis's plain step).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub momentum: Option<f64>,
    /// Which days are streamed.
    pub frames: DayFrames,
    /// The cell types, background first.
    pub types: Vec<CellType>,
    /// α per pair of types.
    pub adhesion: Vec<Vec<f64>>,
    /// Mutation probability per (parent, child).
    pub mutation: Option<Vec<Vec<f64>>>,
    /// Where F cells may start: a PBM or PNG file.
    pub mask: Option<Include>,
    /// The anisotropy field.
    pub anisotropy: Option<Anisotropy>,
    /// The mesh the cells live on (absent: the domain itself).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub surface: Option<Surface>,
}

/// A surface for a mosaic: a built-in shape with its sizes, or an OBJ
/// file. Which keys apply depends on `shape` (docs/scenarios.md).
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Surface {
    /// `ellipsoid`, `stem`, `cap`, `heart-leaf`, `strap-leaf` or `obj`.
    pub shape: String,
    /// Semi-axes of an ellipsoid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radii: Option<[f64; 3]>,
    /// The blend of an ellipsoid towards its box (0 to 0.9).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub square: Option<f64>,
    /// Radius of a stem or a cap.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Length of a stem or a leaf.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub length: Option<f64>,
    /// Width of a leaf.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<f64>,
    /// Height of a cap.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<f64>,
    /// Ribs of a stem.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ribs: Option<i64>,
    /// Rib depth of a stem (share of the radius).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub depth: Option<f64>,
    /// The rim of a cap, degrees from the top.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rim: Option<i64>,
    /// The cup of a leaf (share of the width).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cup: Option<f64>,
    /// Rows of the tessellation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rings: Option<i64>,
    /// Columns of the tessellation.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub segments: Option<i64>,
    /// The OBJ file (`shape = "obj"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub file: Option<Include>,
    /// `cylinder` (around z) or `plane` (x, y): how the mask's (u, v) is
    /// read on the surface.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub control: Option<String>,
}

/// A growth table column.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Column {
    /// The measurement's name.
    pub name: String,
    /// One value per age, in the table's unit.
    pub values: Vec<f64>,
    /// When set, `values` are girths (circumferences) of an elliptical
    /// section whose axes are in this ratio e ≥ 1 (1: a circle), read as
    /// the diameter 2R of the major axis (growth paper Sec. 6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub girth: Option<f64>,
}

/// A growth table.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Table {
    /// The length unit, for documents.
    pub unit: String,
    /// `"linear"` or `"monotone-cubic"`.
    pub interpolation: String,
    /// Ages, months, increasing.
    pub ages: Vec<f64>,
    /// The measured features, in the order the body model uses them.
    pub columns: Vec<Column>,
}

/// A gait channel.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Channel {
    /// The cylinder it bends.
    pub cylinder: String,
    /// Phase offset in samples.
    pub shift: i64,
    /// Bends, whole degrees, one per sample.
    pub degrees: Vec<i64>,
}

/// A gait.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Gait {
    /// Frames per stride.
    pub frames_per_stride: i64,
    /// The share of the stride each hoof is on the ground from its
    /// channel's sample 0 (with `stride_seconds`); without it the lowest
    /// fore and hind hooves support the body at every phase.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duty_factor: Option<f64>,
    /// The stride's duration, seconds (the suspension's flight time).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stride_seconds: Option<f64>,
    /// The joints it moves.
    pub channels: Vec<Channel>,
}

/// `[body]`: a body grown by a table: a built-in one (`model`) or the
/// user's (`mesh` and `cylinders`).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Body {
    /// `"horse"` or `"cow"`.
    pub model: Option<String>,
    /// An OBJ mesh (`docs/body.md`).
    pub mesh: Option<Include>,
    /// A cylinder file (`docs/body.md`).
    pub cylinders: Option<Include>,
    /// Frames.
    pub frames: i64,
    /// Age of the first frame, months.
    pub first_age: f64,
    /// Age of the last frame, months.
    pub last_age: f64,
    /// The growth data.
    pub table: Table,
    /// The joint motion, if any.
    pub gait: Option<Gait>,
}

/// The shrinkwrap.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Wrap {
    /// m: meridians, a multiple of 4.
    pub meridians: i64,
    /// p: parallels, odd.
    pub parallels: i64,
    /// V0, or a range it is drawn from per frame.
    pub target: Drawn,
    /// ΔV, or a range it is drawn from per frame.
    pub step: Drawn,
    /// The iteration cap.
    pub max_iterations: i64,
    /// |V − V0| / V0 beyond which an edge is split (5 % in the paper).
    pub split_tolerance: f64,
    /// The terms of V: `"normalised"` (the paper's eqs. 1–2, the
    /// default) or `"constant"`.
    #[serde(default)]
    pub weights: morphogen::shrinkwrap::Weights,
}

/// A number, or a range `[lo, hi]` a run draws it from uniformly (the
/// bones paper's random parameter values, Summary and Fig. 3).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(untagged)]
pub enum Drawn {
    /// The number itself.
    Number(f64),
    /// `[lo, hi]`.
    Range(Vec<f64>),
}

/// Which skeletons are wrapped.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(untagged)]
pub enum BoneFrames {
    /// `"final"`.
    Keyword(String),
    /// `{ every_step_from = k }` or `{ seeds = n }`.
    Table(BoneFrameTable),
}

/// The table forms of [`BoneFrames`].
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoneFrameTable {
    /// Every step from this one.
    pub every_step_from: Option<i64>,
    /// This many skeletons from seeds s, s + 1, …
    pub seeds: Option<i64>,
}

/// `[bones]`.
#[derive(Debug, Clone, Deserialize, Serialize)]
pub struct Bones {
    /// The skeleton's grammar.
    pub grammar: Include,
    /// Which skeletons are wrapped.
    pub frames: BoneFrames,
    /// The shrinkwrap.
    pub wrap: Wrap,
    /// Every other key: a setting or constant of the skeleton's grammar
    /// and its value (`n = 8`), written into the grammar's text as
    /// `[lsystem]`'s are.
    #[serde(flatten)]
    pub constants: std::collections::BTreeMap<String, toml::Value>,
}
