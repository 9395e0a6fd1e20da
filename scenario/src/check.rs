//! Validation at the door: a [`schema::File`] is checked once into the
//! core's types ([`Checked`]); every value out of range is an [`Invalid`]
//! naming its key and what is allowed. After this nothing saturates.

use morphogen::body::gait::Channel as CoreChannel;
use morphogen::body::gait::Gait as CoreGait;
use morphogen::body::gait::{Footfall, gravity};
use morphogen::body::table::Column as CoreColumn;
use morphogen::body::{
    BodyError, BodyModel, BodyParams, Cylinder, GrowthTable, Interpolation, Label, Mesh, Skeleton,
};
use morphogen::bones::{BonesParams, Frames as BoneFramesCore, MCU_VERTICES};
use morphogen::fx::{Angle, Fx};
use morphogen::growth::Sigmoid as CoreSigmoid;
use morphogen::growth_curve;
use morphogen::horn::{HornParams, MAX_MODULES, MAX_RING_POINTS, Module};
use morphogen::mosaic::{
    self, Anisotropy as CoreAnisotropy, CellType as CoreCellType, ControlVector as CoreVector,
    Domain as CoreDomain, Frames as DayFramesCore, MAX_SELF_ADHESION, MAX_TYPES, Mask,
    Params as MosaicParams,
};
use morphogen::preset::{Model, Preset};
use morphogen::shrinkwrap::WrapParams;
use morphogen::stream::PresetName;

use crate::body_files::{self, USER_CYLINDERS};
use crate::constants;
use crate::mask;
use crate::schema::{self, BoneFrames, DayFrames, File, Include};
use crate::spelling;
use crate::surface::{self, SurfaceSpec};
use crate::unsupported;
pub use crate::value::Invalid;
use crate::value::{Result, decimal, fx, int, invalid, shown};

/// Reads the file an [`Include`] names.
pub trait Files {
    /// The bytes of `path` (relative to the scenario file).
    ///
    /// # Errors
    /// Why it cannot be read.
    fn read(&self, path: &str) -> std::result::Result<Vec<u8>, String>;
}

/// A built-in body model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BuiltinBody {
    /// The quarter horse.
    Horse,
    /// The Holstein.
    Cow,
}

impl BuiltinBody {
    /// Its name in a scenario.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            BuiltinBody::Horse => "horse",
            BuiltinBody::Cow => "cow",
        }
    }

    /// The core's model.
    #[must_use]
    pub fn model(self) -> &'static BodyModel<'static> {
        match self {
            BuiltinBody::Horse => &morphogen::body::quadruped::HORSE,
            BuiltinBody::Cow => &morphogen::body::quadruped::COW,
        }
    }
}

/// The body a `[body]` scenario grows.
#[derive(Debug, Clone)]
pub enum BodyShape {
    /// A built-in body (`model`).
    Builtin(BuiltinBody),
    /// The user's mesh and cylinders (`mesh`, `cylinders`).
    User(Box<UserBody>),
}

/// A user's body, read from its mesh and cylinder files and bound.
#[derive(Debug, Clone)]
pub struct UserBody {
    /// The cylinders, root first.
    pub cylinders: Vec<Cylinder>,
    /// The age the mesh shows, months.
    pub model_age: Fx,
    /// The mesh's vertices.
    pub vertices: Vec<[Fx; 3]>,
    /// The mesh's triangles.
    pub triangles: Vec<[u32; 3]>,
}

impl BodyShape {
    /// Calls `f` with the core's model of this body.
    fn with_model<R>(&self, f: impl FnOnce(&BodyModel<'_>) -> R) -> R {
        match self {
            BodyShape::Builtin(b) => f(b.model()),
            BodyShape::User(u) => f(&BodyModel {
                cylinders: &u.cylinders,
                mesh: Mesh::Indexed {
                    vertices: &u.vertices,
                    triangles: &u.triangles,
                },
                model_age: u.model_age,
            }),
        }
    }
}

/// A checked model, owning every table its core parameters borrow.
#[derive(Debug, Clone)]
pub enum Checked {
    /// `[curve]`.
    Curve(growth_curve::Params),
    /// `[horn]`: the parameters besides the two tables, and the tables.
    Horn {
        /// Every scalar (its slices are empty here).
        params: HornParams<'static>,
        /// Table 1.
        modules: Vec<Module>,
        /// The outline.
        outline: Vec<[Fx; 2]>,
    },
    /// `[lsystem]`: the grammar text.
    LSystem(String),
    /// `[mosaic]`.
    Mosaic {
        /// Every scalar (its slices are empty here).
        params: Box<MosaicParams<'static>>,
        /// The cell types.
        types: Vec<CoreCellType>,
        /// The frame days, if listed.
        days: Option<Vec<u16>>,
        /// The mask (width, height, packed rows).
        mask: Option<(u16, u16, Vec<u8>)>,
        /// The anisotropy's weight and width, and its vectors.
        anisotropy: Option<(Fx, Fx, Vec<CoreVector>)>,
        /// The surface, if the cells live on a mesh.
        surface: Option<SurfaceSpec>,
    },
    /// `[body]`.
    Body {
        /// The body.
        model: BodyShape,
        /// Frames, first and last age, frames per stride.
        frames: u16,
        /// Age of the first frame.
        first_age: Fx,
        /// Age of the last frame.
        last_age: Fx,
        /// Frames per stride (1 without a gait).
        frames_per_stride: u16,
        /// The table's unit.
        unit: String,
        /// The table's interpolation.
        interpolation: Interpolation,
        /// Ages.
        ages: Vec<Fx>,
        /// Columns: name and values.
        columns: Vec<(Label, Vec<Fx>)>,
        /// Gait channels: cylinder, shift, degrees.
        gait: Option<Vec<(Label, u8, Vec<i16>)>>,
        /// The gait's footfall timing, if any.
        footfall: Option<Footfall>,
    },
    /// `[bones]`.
    Bones {
        /// The grammar text.
        grammar: String,
        /// The wrap.
        wrap: WrapParams,
        /// The frames.
        frames: BoneFramesCore,
    },
}

impl Checked {
    /// Calls `f` with the core's [`Preset`] of these parameters (they
    /// borrow from `self`, so they live for the call).
    pub fn with_preset<R>(
        &self,
        name: &str,
        summary: &str,
        seed: u64,
        f: impl FnOnce(&Preset<'_>) -> R,
    ) -> R {
        let preset = |model| Preset {
            name,
            summary,
            default_seed: seed,
            model,
        };
        match self {
            Checked::Curve(p) => f(&preset(Model::GrowthCurve(*p))),
            Checked::Horn {
                params,
                modules,
                outline,
            } => {
                let params = HornParams {
                    modules,
                    outline,
                    ..*params
                };
                f(&preset(Model::Horn(&params)))
            }
            Checked::LSystem(grammar) => f(&preset(Model::LSystem(grammar))),
            Checked::Mosaic {
                params,
                types,
                days,
                mask,
                anisotropy,
                surface,
            } => {
                let params = MosaicParams {
                    surface: surface.as_ref().map(SurfaceSpec::surface),
                    types,
                    frames: days
                        .as_deref()
                        .map_or(DayFramesCore::EveryDay, DayFramesCore::Days),
                    mask: mask.as_ref().map(|(width, height, bits)| Mask {
                        width: *width,
                        height: *height,
                        bits,
                    }),
                    anisotropy: anisotropy.as_ref().map(|(weight, width, vectors)| {
                        CoreAnisotropy {
                            vectors,
                            width: *width,
                            weight: *weight,
                        }
                    }),
                    ..**params
                };
                f(&preset(Model::Mosaic(&params)))
            }
            Checked::Body {
                model,
                frames,
                first_age,
                last_age,
                frames_per_stride,
                unit,
                interpolation,
                ages,
                columns,
                gait,
                footfall,
            } => {
                let columns = core_columns(columns);
                let table = GrowthTable {
                    unit,
                    ages,
                    columns: &columns,
                    interpolation: *interpolation,
                };
                let channels: Vec<CoreChannel<'_>> = gait
                    .iter()
                    .flatten()
                    .map(|(cylinder, shift, degrees)| CoreChannel {
                        cylinder: *cylinder,
                        shift: *shift,
                        degrees,
                    })
                    .collect();
                let core_gait = CoreGait {
                    channels: &channels,
                    footfall: *footfall,
                };
                model.with_model(|model| {
                    let params = BodyParams {
                        model,
                        table: &table,
                        frames: *frames,
                        first_age: *first_age,
                        last_age: *last_age,
                        gait: gait.as_ref().map(|_| &core_gait),
                        frames_per_stride: *frames_per_stride,
                    };
                    f(&Preset {
                        name,
                        summary,
                        default_seed: seed,
                        model: Model::Body(&params),
                    })
                })
            }
            Checked::Bones {
                grammar,
                wrap,
                frames,
            } => {
                let params = BonesParams {
                    grammar,
                    wrap: *wrap,
                    frames: *frames,
                };
                f(&preset(Model::Bones(&params)))
            }
        }
    }
}

/// The longest name a stream header holds.
pub const NAME_BYTES: usize = 32;

/// Checks a scenario's name: 1 to [`NAME_BYTES`] bytes of lower-case
/// letters, digits, `-`, `_` and `.` (not starting with `.`), so that a
/// name is never a path.
///
/// # Errors
/// What is wrong with it.
pub fn name(name: &str) -> Result<()> {
    let ok = !name.is_empty()
        && name.len() <= NAME_BYTES.min(PresetName::new().capacity())
        && !name.starts_with('.')
        && name
            .bytes()
            .all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b"-_.".contains(&b));
    if ok {
        Ok(())
    } else {
        invalid(
            "name",
            format!(
                "{name:?} is not a name (allowed: 1 to {NAME_BYTES} of a-z 0-9 - _ ., not starting with .)"
            ),
        )
    }
}

/// Checks `file` into the core's types, reading included files through
/// `files`.
///
/// # Errors
/// The first value out of range, naming its key.
pub fn check(file: &File, files: &dyn Files) -> Result<Checked> {
    name(&file.name)?;
    let given: Vec<&str> = [
        ("curve", file.curve.is_some()),
        ("horn", file.horn.is_some()),
        ("lsystem", file.lsystem.is_some()),
        ("mosaic", file.mosaic.is_some()),
        ("body", file.body.is_some()),
        ("bones", file.bones.is_some()),
    ]
    .iter()
    .filter(|(_, on)| *on)
    .map(|(n, _)| *n)
    .collect();
    if given.len() != 1 {
        return invalid(
            "",
            format!(
                "a scenario has exactly one model table, this one has {} (allowed: [curve], [horn], [lsystem], [mosaic], [body], [bones])",
                if given.is_empty() {
                    "none".to_string()
                } else {
                    given.join(", ")
                }
            ),
        );
    }
    if let Some(c) = &file.curve {
        return curve(c);
    }
    if let Some(h) = &file.horn {
        return horn(h);
    }
    if let Some(l) = &file.lsystem {
        return lsystem(l, files);
    }
    if let Some(m) = &file.mosaic {
        return mosaic(m, files);
    }
    if let Some(b) = &file.body {
        return body(b, files);
    }
    match &file.bones {
        Some(b) => bones(b, files),
        None => invalid("", "no model table"),
    }
}

// ----------------------------------------------------------------- units

/// A percentage as a ratio in 16.16.
fn percent(key: &str, v: f64, lo: f64, hi: f64) -> Result<Fx> {
    crate::value::note(key, v, lo, hi, false);
    if !v.is_finite() || v < lo || v > hi {
        return invalid(
            key,
            format!("{} % is out of range (allowed: {lo} to {hi} %)", shown(v)),
        );
    }
    Ok(Fx::from_bits((v * 65536.0 / 100.0).round() as i32))
}

/// Degrees as a binary angle: whole degrees exactly as the core's
/// `Angle::from_degrees`, others rounded to the nearest unit.
fn degrees(key: &str, v: f64) -> Result<Angle> {
    crate::value::note(key, v, -3600.0, 3600.0, false);
    if !v.is_finite() || v.abs() > 3600.0 {
        return invalid(
            key,
            format!("{}° is out of range (allowed: -3600 to 3600)", shown(v)),
        );
    }
    if v.fract() == 0.0 {
        return Ok(Angle::from_degrees(v as i32));
    }
    let turns = v / 360.0;
    let units = (turns * 4_294_967_296.0)
        .round()
        .rem_euclid(4_294_967_296.0);
    Ok(Angle(units as u32))
}

fn text(include: &Include, key: &str, files: &dyn Files) -> Result<String> {
    match include {
        Include::Inline { text, .. } => Ok(text.clone()),
        Include::Path(path) => {
            let bytes = files
                .read(path)
                .or_else(|e| invalid(key, format!("cannot read {path}: {e}")))?;
            crate::utf8(bytes).or_else(|e| invalid(key, format!("{path}:{e}")))
        }
    }
}

/// `text` parsed, its errors named by the file `include` names; `constant`
/// hears each `name = value` it defines (name and value).
fn parse_grammar(
    text: &str,
    include: &Include,
    key: &str,
    constant: impl FnMut(&str, Fx),
) -> Result<Box<morphogen::lsys::Grammar>> {
    grammar(text, include_name(include), constant).or_else(|message| invalid(key, message))
}

/// The grammar `text` (from the file `file`, which errors name) parsed;
/// `constant` hears each `name = value` it defines (name and value). A
/// constant that no expression reads and is named like a setting is
/// refused as a misspelt setting (`scenario/src/spelling.rs`), in every
/// grammar a scenario or `morphogen run --grammar` gives.
///
/// # Errors
/// The first problem, as `file:line:column: what`.
pub fn grammar(
    text: &str,
    file: &str,
    mut constant: impl FnMut(&str, Fx),
) -> std::result::Result<Box<morphogen::lsys::Grammar>, String> {
    let at = |line: u32, column: u32, what: &dyn std::fmt::Display| {
        Err(format!("{file}:{line}:{column}: {what}"))
    };
    let mut grammar = Box::new(morphogen::lsys::Grammar::new());
    let mut misspelt = None;
    let parsed = grammar.parse_with(text, |d| {
        if misspelt.is_none() {
            misspelt = spelling::misspelt(&d);
        }
        constant(d.name, d.value);
    });
    // A misspelt setting first: it explains a missing `n` too (`N = 2`).
    match (parsed, misspelt) {
        (_, Some((line, column, message))) => at(line, column, &message),
        (Ok(()), None) => Ok(grammar),
        (Err(e), None) => match spelling::misspelt_on_line(text, e.line) {
            Some((column, message)) => at(e.line, column, &message),
            None => at(e.line, e.column, &unsupported::explained(&e.kind)),
        },
    }
}

/// `[lsystem]`: the grammar with the table's settings and constants
/// written in; each of its constants is a control.
fn lsystem(l: &schema::LSystem, files: &dyn Files) -> Result<Checked> {
    let key = "lsystem.grammar";
    let given = text(&l.grammar, key, files)?;
    let text = constants::apply(&given, &l.constants, "lsystem", include_name(&l.grammar))?;
    let mut defined = Vec::new();
    parse_grammar(&text, &l.grammar, key, |name, v| {
        defined.push((name.to_string(), decimal(v)));
    })?;
    constants::note_all("lsystem", &defined);
    Ok(Checked::LSystem(text))
}

/// The settings a bone's skeleton grammar may not set: they place and
/// animate plants, which a skeleton is not.
const PLANT_ONLY_SETTINGS: [&str; 3] = ["plants", "spacing", "animate"];

/// The file an include names, or "grammar" for unnamed inline text.
fn include_name(include: &Include) -> &str {
    match include {
        Include::Path(path)
        | Include::Inline {
            name: Some(path), ..
        } => path.as_str(),
        Include::Inline { name: None, .. } => "grammar",
    }
}

// ---------------------------------------------------------------- models

fn sigmoid(key: &str, s: &schema::Sigmoid, span: Option<Fx>) -> Result<CoreSigmoid> {
    let span = match (span, s.span) {
        (Some(fixed), None) => fixed,
        (Some(_), Some(_)) => {
            return invalid(
                format!("{key}.span"),
                "a horn module's span is its delay T: remove span (allowed: centre, width)",
            );
        }
        (None, Some(v)) => fx(&format!("{key}.span"), v, 1.0, 32767.0)?,
        (None, None) => return invalid(format!("{key}.span"), "missing (days, 1 to 32767)"),
    };
    Ok(CoreSigmoid {
        centre: fx(&format!("{key}.centre"), s.centre, -32767.0, 32767.0)?,
        width: fx(&format!("{key}.width"), s.width, 0.01, 32767.0)?,
        span,
    })
}

fn curve(c: &schema::Curve) -> Result<Checked> {
    Ok(Checked::Curve(growth_curve::Params {
        growth: sigmoid("curve.growth", &c.growth, None)?,
        days: int("curve.days", c.days, 1, 32767)?,
    }))
}

fn horn(h: &schema::Horn) -> Result<Checked> {
    let delay_days: u16 = int("horn.delay_days", h.delay_days, 1, 32767)?;
    let growth = sigmoid(
        "horn.growth",
        &h.growth,
        Some(Fx::from_int(i32::from(delay_days))),
    )?;
    if h.modules.is_empty() || h.modules.len() > MAX_MODULES {
        return invalid(
            "horn.modules",
            format!(
                "{} modules (allowed: 1 to {MAX_MODULES}, horn::MAX_MODULES)",
                h.modules.len()
            ),
        );
    }
    let mut modules = Vec::with_capacity(h.modules.len());
    for (i, m) in h.modules.iter().enumerate() {
        let key = |f: &str| format!("horn.modules[{i}].{f}");
        modules.push(Module {
            positioner_scale: percent(&key("positioner_scale"), m.positioner_scale, 0.01, 10000.0)?,
            base_scale: percent(&key("base_scale"), m.base_scale, 0.01, 10000.0)?,
            bend: degrees(&key("bend"), m.bend)?,
            twist: degrees(&key("twist"), m.twist)?,
            path_radius: fx(&key("path_radius"), m.path_radius, 0.01, 32767.0)?,
        });
    }
    for i in 1..modules.len() {
        if modules[i].positioner_scale != modules[i - 1].base_scale {
            return invalid(
                format!("horn.modules[{i}].positioner_scale"),
                format!(
                    "must equal the base_scale of module {} ({} %) so the horn is continuous (paper Sec. 6)",
                    i,
                    h.modules[i - 1].base_scale
                ),
            );
        }
    }
    let outline = match (&h.outline, &h.section) {
        (Some(points), None) => {
            if points.len() < 3 || points.len() > 1024 {
                return invalid(
                    "horn.outline",
                    format!("{} points (allowed: 3 to 1024)", points.len()),
                );
            }
            points
                .iter()
                .enumerate()
                .map(|(i, [y, z])| {
                    let key = format!("horn.outline[{i}]");
                    Ok([
                        fx(&key, *y, -1000.0, 1000.0)?,
                        fx(&key, *z, -1000.0, 1000.0)?,
                    ])
                })
                .collect::<Result<Vec<_>>>()?
        }
        (None, Some(section)) => horn_section(
            fx("horn.section.radius", section.radius, 0.01, 500.0)?,
            fx(
                "horn.section.triangularity",
                section.triangularity,
                0.0,
                1.0,
            )?,
        ),
        _ => {
            return invalid(
                "horn.outline",
                "give the cross-section as `outline` (points) or as `section` (radius, triangularity), one of them",
            );
        }
    };
    let years: u16 = int("horn.years", h.years, 1, modules.len() as i64)?;
    let params = HornParams {
        modules: &[],
        outline: &[],
        ring_points: int("horn.ring_points", h.ring_points, 3, MAX_RING_POINTS as i64)?,
        rings_per_module: int("horn.rings_per_module", h.rings_per_module, 1, 1024)?,
        delay_days,
        growth,
        frames_per_year: int("horn.frames_per_year", h.frames_per_year, 1, 365)?,
        years,
    };
    Ok(Checked::Horn {
        params,
        modules,
        outline,
    })
}

/// Points of a `horn.section`.
const SECTION_POINTS: u32 = 60;

/// The cross-section between a circle of radius `radius` (triangularity 0)
/// and the equilateral triangle of the same area with a corner up
/// (triangularity 1), as the horn paper describes bovid sections (Sec. 2:
/// "from almost circular to almost triangular"): the polar radii blended,
/// (1 − t)·R + t·ρ / cos δ, with ρ = R·√(π / 3√3) the triangle's inradius
/// and δ the angle to the nearest side's normal. Counter-clockwise from the
/// top corner, in fixed point (the same points on every machine).
fn horn_section(radius: Fx, triangularity: Fx) -> Vec<[Fx; 2]> {
    use morphogen::fx::{Angle, Real};
    // √(π / 3√3) = 0.777_551…, in Q16.
    let inradius = radius * Fx::from_bits(50_958);
    let up = Angle::from_degrees(90);
    (0..SECTION_POINTS)
        .map(|k| {
            let turn = Angle::from_turn_ratio(i64::from(k), i64::from(SECTION_POINTS));
            // The sides' normals are 60° either side of each corner: δ is
            // the angle from the corner's 120° sector's middle, less 60°.
            let sector = Angle::from_turn_ratio(
                i64::from(k % (SECTION_POINTS / 3)),
                i64::from(SECTION_POINTS),
            );
            let delta = Angle(sector.0.wrapping_sub(Angle::from_degrees(60).0));
            let triangle = inradius / <Fx as Real>::cos(delta);
            let r = radius + (triangle - radius) * triangularity;
            let phi = Angle(up.0.wrapping_add(turn.0));
            [r * <Fx as Real>::cos(phi), r * <Fx as Real>::sin(phi)]
        })
        .collect()
}

fn matrix(key: &str, rows: &[Vec<f64>], n: usize) -> Result<[[Fx; MAX_TYPES]; MAX_TYPES]> {
    if rows.len() != n || rows.iter().any(|r| r.len() != n) {
        return invalid(
            key,
            format!("must be {n} rows of {n} numbers, one per pair of types (allowed: 0 to 1)"),
        );
    }
    let mut t = [[Fx::ZERO; MAX_TYPES]; MAX_TYPES];
    for (i, row) in rows.iter().enumerate() {
        for (j, v) in row.iter().enumerate() {
            t[i][j] = fx(&format!("{key}[{i}][{j}]"), *v, 0.0, 1.0)?;
        }
    }
    Ok(t)
}

/// How far past 1 a sum of probabilities may be: decimals that sum to 1
/// do not always in binary (`0.1 + 0.2 + 0.7` is 1.0000000000000002).
const PROBABILITY_SLACK: f64 = 1e-9;

/// A cell type as messages name it: its name, or `type i`.
fn type_label(types: &[schema::CellType], i: usize) -> String {
    match types.get(i).map(|t| t.name.as_str()) {
        Some(name) if !name.is_empty() => name.to_string(),
        _ => format!("type {i}"),
    }
}

/// `label value + label value…` and their sum.
fn terms(parts: impl Iterator<Item = (String, f64)>) -> (String, f64) {
    let parts: Vec<(String, f64)> = parts.collect();
    let sum = parts.iter().map(|(_, v)| v).sum();
    let text: Vec<String> = parts
        .iter()
        .map(|(label, v)| format!("{label} {}", shown(*v)))
        .collect();
    (text.join(" + "), sum)
}

/// The initial probabilities may leave a share to type 0 but not pass 1
/// (draws past 1 never happen: the last types would lose their share),
/// and a mutation row is the probabilities of a child of that type
/// becoming each other type, so its entries off the diagonal sum to at
/// most 1; the diagonal, keeping the parent's type, is the rest of the
/// row (thesis Sec. 3.2.1.2) and is implied.
fn probabilities_sum_to_at_most_one(m: &schema::Mosaic) -> Result<()> {
    let (text, sum) = terms(
        m.types
            .iter()
            .enumerate()
            .map(|(i, t)| (type_label(&m.types, i), t.initial_probability)),
    );
    if sum > 1.0 + PROBABILITY_SLACK {
        let mut running = 0.0;
        let past = m
            .types
            .iter()
            .position(|t| {
                running += t.initial_probability;
                running > 1.0 + PROBABILITY_SLACK
            })
            .unwrap_or(0);
        return invalid(
            format!("mosaic.types[{past}].initial_probability"),
            format!(
                "the initial probabilities sum to {} ({text}), past 1 (allowed: a sum of at most 1; what it leaves to 1 starts as type 0, {})",
                shown(sum),
                type_label(&m.types, 0)
            ),
        );
    }
    for (i, row) in m.mutation.iter().flatten().enumerate() {
        if row.get(i).is_some_and(|&d| d != 0.0) {
            return invalid(
                format!("mosaic.mutation[{i}][{i}]"),
                format!(
                    "{} on the diagonal: the diagonal is the probability of not mutating (a child of {} keeping its type), 1 minus the rest of the row, and is implied (allowed: 0)",
                    shown(row[i]),
                    type_label(&m.types, i)
                ),
            );
        }
        let (text, sum) = terms(
            row.iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(j, &v)| (type_label(&m.types, j), v)),
        );
        if sum > 1.0 + PROBABILITY_SLACK {
            return invalid(
                format!("mosaic.mutation[{i}]"),
                format!(
                    "a child of {} mutates with probabilities summing to {} ({text}), past 1 (allowed: at most 1 off the diagonal)",
                    type_label(&m.types, i),
                    shown(sum)
                ),
            );
        }
    }
    Ok(())
}

fn mosaic(m: &schema::Mosaic, files: &dyn Files) -> Result<Checked> {
    let size = [
        fx("mosaic.domain.size[0]", m.domain.size[0], 1.0, 16384.0)?,
        fx("mosaic.domain.size[1]", m.domain.size[1], 1.0, 16384.0)?,
    ];
    let n = m.types.len();
    if n == 0 || n > MAX_TYPES {
        return invalid(
            "mosaic.types",
            format!("{n} types (allowed: 1 to {MAX_TYPES}, mosaic::MAX_TYPES)"),
        );
    }
    let mut types = Vec::with_capacity(n);
    for (i, t) in m.types.iter().enumerate() {
        let key = |f: &str| format!("mosaic.types[{i}].{f}");
        let mut colour = [0u8; 3];
        for (c, v) in colour.iter_mut().zip(t.colour) {
            *c = int(&key("colour"), v, 0, 255)?;
        }
        types.push(CoreCellType {
            colour,
            division_days: int(&key("division_days"), t.division_days, 1, 1024)?,
            initial_probability: fx(&key("initial_probability"), t.initial_probability, 0.0, 1.0)?,
        });
    }
    let adhesion = matrix("mosaic.adhesion", &m.adhesion, n)?;
    let pairs = (0..n).flat_map(|i| (0..n).map(move |j| (i, j)));
    if let Some((i, j)) = pairs
        .into_iter()
        .find(|&(i, j)| adhesion[i][j] != adhesion[j][i])
    {
        return invalid(
            format!("mosaic.adhesion[{i}][{j}]"),
            "adhesion is symmetric: α[i][j] must equal α[j][i]",
        );
    }
    if let Some(i) = (0..n).find(|&i| adhesion[i][i] > MAX_SELF_ADHESION) {
        return invalid(
            format!("mosaic.adhesion[{i}][{i}]"),
            "a type's adhesion with itself is at most 0.95: its cells must repel each other to keep their size",
        );
    }
    let mutation = match &m.mutation {
        Some(rows) => matrix("mosaic.mutation", rows, n)?,
        None => [[Fx::ZERO; MAX_TYPES]; MAX_TYPES],
    };
    probabilities_sum_to_at_most_one(m)?;
    let days: u16 = int("mosaic.days", m.days, 0, 4096)?;
    let frame_days = match &m.frames {
        DayFrames::Keyword(k) if k == "every-day" => None,
        DayFrames::Keyword(k) => {
            return invalid(
                "mosaic.frames",
                format!("{k:?} (allowed: \"every-day\" or a list of days)"),
            );
        }
        DayFrames::Days(list) => {
            let mut out = Vec::with_capacity(list.len());
            for (i, d) in list.iter().enumerate() {
                let key = format!("mosaic.frames[{i}]");
                if *d > i64::from(days) && *d <= 4096 {
                    // Most often a shorter run (`--set mosaic.days=…`) than
                    // the frames were written for: name the day it ends.
                    return invalid(
                        key,
                        format!(
                            "day {d} is past the run's last day, mosaic.days = {days} (allowed: 0 to mosaic.days, or \"every-day\")"
                        ),
                    );
                }
                let d: u16 = int(&key, *d, 0, i64::from(days))?;
                if out.last().is_some_and(|&p| p >= d) {
                    return invalid(
                        key,
                        "days must increase (allowed: 0 to mosaic.days, increasing)",
                    );
                }
                out.push(d);
            }
            Some(out)
        }
    };
    let mask = match &m.mask {
        None => None,
        Some(include) => {
            let bytes = match include {
                Include::Path(path) => files
                    .read(path)
                    .or_else(|e| invalid("mosaic.mask", format!("cannot read {path}: {e}")))?,
                Include::Inline { text, .. } => text.clone().into_bytes(),
            };
            Some(mask::read(&bytes).or_else(|e| invalid("mosaic.mask", e))?)
        }
    };
    let anisotropy = match &m.anisotropy {
        None => None,
        Some(a) => {
            if a.vectors.len() > mosaic::MAX_CONTROL_VECTORS {
                return invalid(
                    "mosaic.anisotropy.vectors",
                    format!(
                        "{} vectors (allowed: 0 to {}, mosaic::MAX_CONTROL_VECTORS)",
                        a.vectors.len(),
                        mosaic::MAX_CONTROL_VECTORS
                    ),
                );
            }
            let vectors = a
                .vectors
                .iter()
                .enumerate()
                .map(|(i, v)| {
                    let key = |f: &str| format!("mosaic.anisotropy.vectors[{i}].{f}");
                    Ok(CoreVector {
                        at: [
                            fx(&key("at"), v.at[0], 0.0, 16384.0)?,
                            fx(&key("at"), v.at[1], 0.0, 16384.0)?,
                        ],
                        v: [
                            fx(&key("v"), v.v[0], -1.0, 1.0)?,
                            fx(&key("v"), v.v[1], -1.0, 1.0)?,
                        ],
                    })
                })
                .collect::<Result<Vec<_>>>()?;
            Some((
                fx("mosaic.anisotropy.weight", a.weight, 0.0, 1.0)?,
                fx("mosaic.anisotropy.width", a.width, 0.01, 16384.0)?,
                vectors,
            ))
        }
    };
    let params = MosaicParams {
        domain: CoreDomain {
            size,
            periodic: m.domain.periodic,
        },
        initial_cells: int("mosaic.initial_cells", m.initial_cells, 1, 1 << 24)?,
        types: &[],
        adhesion,
        mutation,
        radius_weight: fx("mosaic.radius_weight", m.radius_weight, 0.01, 16.0)?,
        push_weight: fx("mosaic.push_weight", m.push_weight, 0.0, 1.0)?,
        initial_relaxations: int(
            "mosaic.initial_relaxations",
            m.initial_relaxations,
            0,
            10000,
        )?,
        daily_relaxations: int("mosaic.daily_relaxations", m.daily_relaxations, 0, 10000)?,
        momentum: fx("mosaic.momentum", m.momentum.unwrap_or(0.0), 0.0, 0.95)?,
        days,
        mask: None,
        anisotropy: None,
        frames: DayFramesCore::EveryDay,
        surface: None,
    };
    let surface = match &m.surface {
        None => None,
        Some(s) => Some(surface::check(s, &|include| match include {
            Include::Path(path) => files
                .read(path)
                .or_else(|e| invalid("mosaic.surface.file", format!("cannot read {path}: {e}"))),
            Include::Inline { text, .. } => Ok(text.clone().into_bytes()),
        })?),
    };
    Ok(Checked::Mosaic {
        params: Box::new(params),
        types,
        days: frame_days,
        mask,
        anisotropy,
        surface,
    })
}

fn label(key: &str, name: &str) -> Result<Label> {
    Label::try_new(name).ok_or_else(|| Invalid {
        key: key.into(),
        message: format!(
            "{name:?} is longer than {} bytes (body::LABEL_BYTES)",
            morphogen::body::LABEL_BYTES
        ),
    })
}

fn body(b: &schema::Body, files: &dyn Files) -> Result<Checked> {
    let t = &b.table;
    let interpolation = match t.interpolation.as_str() {
        "linear" => Interpolation::Linear,
        "monotone-cubic" => Interpolation::MonotoneCubic,
        other => {
            return invalid(
                "body.table.interpolation",
                format!("{other:?} (allowed: \"linear\", \"monotone-cubic\")"),
            );
        }
    };
    if t.ages.is_empty() || t.ages.len() > 64 {
        return invalid(
            "body.table.ages",
            format!("{} ages (allowed: 1 to 64)", t.ages.len()),
        );
    }
    let mut ages = Vec::with_capacity(t.ages.len());
    for (i, a) in t.ages.iter().enumerate() {
        let age = fx(&format!("body.table.ages[{i}]"), *a, 0.0, 1200.0)?;
        if ages.last().is_some_and(|&p| p >= age) {
            return invalid(format!("body.table.ages[{i}]"), "ages must increase");
        }
        ages.push(age);
    }
    let mut columns = Vec::with_capacity(t.columns.len());
    for (i, c) in t.columns.iter().enumerate() {
        let key = format!("body.table.columns[{i}]");
        if c.values.len() != ages.len() {
            return invalid(
                format!("{key}.values"),
                format!(
                    "{} values for {} ages (allowed: one per age)",
                    c.values.len(),
                    ages.len()
                ),
            );
        }
        let per_length = match c.girth {
            None => 1.0,
            Some(e) if (1.0..=100.0).contains(&e) => girth_to_diameter(e),
            Some(e) => {
                return invalid(
                    format!("{key}.girth"),
                    format!("{e} (allowed: an axis ratio from 1 to 100)"),
                );
            }
        };
        let values = c
            .values
            .iter()
            .enumerate()
            .map(|(j, v)| {
                fx(
                    &format!("{key}.values[{j}]"),
                    *v * per_length,
                    0.0001,
                    30000.0,
                )
            })
            .collect::<Result<Vec<_>>>()?;
        columns.push((label(&format!("{key}.name"), &c.name)?, values));
    }
    let borrowed = core_columns(&columns);
    let table = GrowthTable {
        unit: &t.unit,
        ages: &ages,
        columns: &borrowed,
        interpolation,
    };
    table.validate().map_err(|e| Invalid {
        key: "body.table".into(),
        message: e.to_string(),
    })?;
    let model = match (&b.model, &b.mesh, &b.cylinders) {
        (Some(name), None, None) => BodyShape::Builtin(match name.as_str() {
            "horse" => BuiltinBody::Horse,
            "cow" => BuiltinBody::Cow,
            other => {
                return invalid(
                    "body.model",
                    format!("{other:?} is not a built-in body (allowed: \"horse\", \"cow\")"),
                );
            }
        }),
        (None, Some(mesh), Some(cylinders)) => {
            BodyShape::User(Box::new(user_body(mesh, cylinders, &table, files)?))
        }
        (Some(_), _, _) => {
            return invalid(
                "body.model",
                "a built-in body or your own mesh and cylinders, not both (remove model, or mesh and cylinders)",
            );
        }
        (None, None, _) => {
            return invalid(
                "body.mesh",
                "missing: give model = \"horse\" or \"cow\", or mesh and cylinders",
            );
        }
        (None, Some(_), None) => {
            return invalid(
                "body.cylinders",
                "missing: a mesh is bound to the cylinders of a cylinder file (docs/body.md)",
            );
        }
    };
    // A built-in model reads its columns by position: check the table
    // against it (a user's cylinder file names its columns).
    if let BodyShape::Builtin(body) = &model {
        let mut skeleton = Box::new(Skeleton::<Fx, USER_CYLINDERS>::new());
        skeleton.load(body.model(), &table).map_err(|e| Invalid {
            key: "body.table.columns".into(),
            message: format!("{e} (the {} model needs its columns in order)", body.name()),
        })?;
    }
    let frames: u16 = int("body.frames", b.frames, 1, 10000)?;
    let footfall = match b.gait.as_ref().map(|g| (g.duty_factor, g.stride_seconds)) {
        None | Some((None, None)) => None,
        Some((Some(duty), Some(seconds))) => {
            if gravity(&t.unit).is_none() {
                return invalid(
                    "body.gait.duty_factor",
                    format!(
                        "a flight needs gravity in the table's unit: in, cm, mm or m (not {:?})",
                        t.unit
                    ),
                );
            }
            Some(Footfall {
                duty_factor: fx("body.gait.duty_factor", duty, 0.05, 0.95)?,
                stride_seconds: fx("body.gait.stride_seconds", seconds, 0.05, 10.0)?,
            })
        }
        Some((Some(_), None)) => {
            return invalid("body.gait.stride_seconds", "needed with duty_factor");
        }
        Some((None, Some(_))) => {
            return invalid("body.gait.duty_factor", "needed with stride_seconds");
        }
    };
    let (frames_per_stride, gait) = match &b.gait {
        None => (1, None),
        Some(g) => {
            let mut channels = Vec::with_capacity(g.channels.len());
            for (i, c) in g.channels.iter().enumerate() {
                let key = |f: &str| format!("body.gait.channels[{i}].{f}");
                if c.degrees.is_empty() || c.degrees.len() > 1024 {
                    return invalid(key("degrees"), "1 to 1024 samples");
                }
                let degrees = c
                    .degrees
                    .iter()
                    .map(|d| int(&key("degrees"), *d, -360, 360))
                    .collect::<Result<Vec<i16>>>()?;
                channels.push((
                    label(&key("cylinder"), &c.cylinder)?,
                    int(&key("shift"), c.shift, 0, 255)?,
                    degrees,
                ));
            }
            (
                int("body.gait.frames_per_stride", g.frames_per_stride, 1, 1000)?,
                Some(channels),
            )
        }
    };
    // A channel for a cylinder the body does not have would move nothing.
    if let Some(channels) = &gait {
        let names: Vec<Label> = model.with_model(|m| m.cylinders.iter().map(|c| c.name).collect());
        if let Some(i) = channels.iter().position(|(c, ..)| !names.contains(c)) {
            let known: Vec<&str> = names.iter().map(Label::as_str).collect();
            return invalid(
                format!("body.gait.channels[{i}].cylinder"),
                format!(
                    "{:?} is not a cylinder of this body (allowed: {})",
                    channels[i].0.as_str(),
                    known.join(", ")
                ),
            );
        }
    }
    Ok(Checked::Body {
        model,
        frames,
        first_age: fx("body.first_age", b.first_age, 0.0, 1200.0)?,
        last_age: fx("body.last_age", b.last_age, 0.0, 1200.0)?,
        frames_per_stride,
        unit: t.unit.clone(),
        interpolation,
        ages,
        columns,
        gait,
        footfall,
    })
}

/// The diameter 2R per unit of girth of an elliptical section whose axes
/// are in the ratio `e` (major over minor): the growth paper's (Sec. 6)
/// circumference 2πR·√((e² + 1) / 2e²), the ellipse's perimeter with the
/// two semi-axes' quadratic mean. Correctly rounded `f64` operations, so
/// the same on every machine before the value becomes fixed point.
fn girth_to_diameter(e: f64) -> f64 {
    1.0 / (std::f64::consts::PI * ((e * e + 1.0) / (2.0 * e * e)).sqrt())
}

/// A growth table's columns as the core borrows them.
fn core_columns(columns: &[(Label, Vec<Fx>)]) -> Vec<CoreColumn<'_>> {
    columns
        .iter()
        .map(|(name, values)| CoreColumn {
            name: *name,
            values,
        })
        .collect()
}

/// The user's body: the cylinder file read against the growth `table`,
/// the mesh, and every vertex bound, so that a mistake is named by its
/// file and line here rather than in the middle of a run.
fn user_body(
    mesh: &Include,
    cylinders: &Include,
    table: &GrowthTable<'_>,
    files: &dyn Files,
) -> Result<UserBody> {
    let name = |include: &Include, inline: &str| match include {
        Include::Path(path)
        | Include::Inline {
            name: Some(path), ..
        } => path.clone(),
        Include::Inline { name: None, .. } => inline.to_string(),
    };
    let (mesh_name, cylinders_name) = (name(mesh, "mesh"), name(cylinders, "cylinders"));
    let file = body_files::parse_cylinders(
        &cylinders_name,
        &text(cylinders, "body.cylinders", files)?,
        table,
    )
    .or_else(|e| invalid("body.cylinders", e))?;
    let obj = body_files::parse_obj(&mesh_name, &text(mesh, "body.mesh", files)?)
        .or_else(|e| invalid("body.mesh", e))?;
    let model = BodyModel {
        cylinders: &file.cylinders,
        mesh: Mesh::Indexed {
            vertices: &obj.vertices,
            triangles: &obj.triangles,
        },
        model_age: file.model_age,
    };
    if let Err(e) = morphogen::body::binding_summary::<USER_CYLINDERS>(&model, table) {
        let line = |c: Label| file.lines.get(c.as_str()).copied().unwrap_or(0);
        return Err(
            match (&e, cylinder_of(&e), first_unbindable(&model, table)) {
                (morphogen::Error::Capacity { .. }, _, Some(v)) => Invalid {
                    key: "body.mesh".into(),
                    message: format!(
                        "{mesh_name}:{}: vertex {} lies in more than {} cylinders ({e}); make the cylinders overlap less",
                        obj.vertex_lines.get(v).copied().unwrap_or(0),
                        v + 1,
                        morphogen::body::MAX_BINDINGS
                    ),
                },
                (_, Some(c), _) => Invalid {
                    key: "body.cylinders".into(),
                    message: format!("{cylinders_name}:{}: {e}", line(c)),
                },
                _ => Invalid {
                    key: "body.mesh".into(),
                    message: format!("{mesh_name} with {cylinders_name}: {e}"),
                },
            },
        );
    }
    Ok(UserBody {
        cylinders: file.cylinders,
        model_age: file.model_age,
        vertices: obj.vertices,
        triangles: obj.triangles,
    })
}

/// The first vertex of `model` that cannot be bound (more cylinders hold
/// it than a binding has room for), if any.
fn first_unbindable(model: &BodyModel<'_>, table: &GrowthTable<'_>) -> Option<usize> {
    let mut skeleton = Box::new(Skeleton::<Fx, USER_CYLINDERS>::new());
    skeleton.load(model, table).ok()?;
    (0..model.mesh.vertex_count() as usize).find(|&i| {
        model
            .mesh
            .vertex::<Fx>(i as u32)
            .is_some_and(|p| skeleton.bind(&p).is_err())
    })
}

/// The cylinder an error is about, if any.
fn cylinder_of(e: &morphogen::Error) -> Option<Label> {
    match e {
        morphogen::Error::Body(
            BodyError::ParentOrder { cylinder }
            | BodyError::DegenerateCylinder { cylinder }
            | BodyError::DegenerateFeature { cylinder }
            | BodyError::SingularFeatures { cylinder }
            | BodyError::NegativeSize { cylinder, .. }
            | BodyError::UnknownColumn { cylinder, .. },
        ) => Some(*cylinder),
        _ => None,
    }
}

fn bones(b: &schema::Bones, files: &dyn Files) -> Result<Checked> {
    let key = "bones.grammar";
    if let Some(name) = b
        .constants
        .keys()
        .find(|n| PLANT_ONLY_SETTINGS.contains(&n.as_str()))
    {
        return invalid(
            format!("bones.{name}"),
            format!(
                "`{name}` applies only to L-system plant presets ([lsystem]); a bone's skeleton \
                 is one derivation wrapped once"
            ),
        );
    }
    let given = text(&b.grammar, key, files)?;
    let grammar = constants::apply(&given, &b.constants, "bones", include_name(&b.grammar))?;
    let mut defined = Vec::new();
    let parsed = parse_grammar(&grammar, &b.grammar, key, |name, v| {
        defined.push((name.to_string(), decimal(v)));
    })?;
    constants::note_all("bones", &defined);
    if let Some(a) = constants::assignments(&grammar)
        .into_iter()
        .find(|a| PLANT_ONLY_SETTINGS.contains(&a.name))
    {
        return invalid(
            "bones.grammar",
            format!(
                "{}:{}: `{}` applies only to L-system plant presets ([lsystem]); a bone's \
                 skeleton is one derivation wrapped once, so remove it",
                include_name(&b.grammar),
                a.line,
                a.name
            ),
        );
    }
    if parsed.has_interpretation() {
        return invalid(
            "bones.grammar",
            format!(
                "{}: `interpretation:` rules change only a plant's drawing; a skeleton is the \
                 derived string itself, so a bone grammar cannot have them",
                include_name(&b.grammar)
            ),
        );
    }
    let frames = match &b.frames {
        BoneFrames::Keyword(k) if k == "final" => BoneFramesCore::Final,
        BoneFrames::Keyword(k) => {
            return invalid(
                "bones.frames",
                format!("{k:?} (allowed: \"final\", {{ every_step_from = K }}, {{ seeds = N }})"),
            );
        }
        BoneFrames::Table(t) => match (t.every_step_from, t.seeds) {
            (Some(first), None) => BoneFramesCore::EveryStep {
                // Steps past the grammar's n are not derived.
                first: int(
                    "bones.frames.every_step_from",
                    first,
                    0,
                    i64::from(parsed.settings().steps),
                )?,
            },
            (None, Some(n)) => BoneFramesCore::Seeds(int("bones.frames.seeds", n, 1, 255)?),
            _ => {
                return invalid(
                    "bones.frames",
                    "give one of every_step_from = K or seeds = N",
                );
            }
        },
    };
    let w = &b.wrap;
    let meridians: u8 = int("bones.wrap.meridians", w.meridians, 4, 252)?;
    if !meridians.is_multiple_of(4) {
        return invalid(
            "bones.wrap.meridians",
            format!("{meridians} is not a multiple of 4 (allowed: 4, 8, … 252)"),
        );
    }
    // The initial sphere, m·p + 2 vertices, fits the mesh.
    let most = ((MCU_VERTICES as i64 - 2) / i64::from(meridians)).min(255);
    let most = most - (1 - most % 2); // odd
    if w.parallels > most && w.parallels <= 255 {
        return invalid(
            "bones.wrap.parallels",
            format!(
                "{} parallels of {meridians} meridians make a sphere of {} vertices, more than \
                 the shrinkwrap mesh holds (MCU_VERTICES = {MCU_VERTICES}; allowed with \
                 {meridians} meridians: 1 to {most})",
                w.parallels,
                w.parallels * i64::from(meridians) + 2
            ),
        );
    }
    let parallels: u8 = int("bones.wrap.parallels", w.parallels, 1, most)?;
    if parallels.is_multiple_of(2) {
        return invalid(
            "bones.wrap.parallels",
            format!("{parallels} is even (allowed: odd, 1 to 255)"),
        );
    }
    let (target, target_max) = drawn("bones.wrap.target", &w.target, 0.01, 1000.0)?;
    let (step, step_max) = drawn("bones.wrap.step", &w.step, 0.0001, 1000.0)?;
    let wrap = WrapParams {
        meridians,
        parallels,
        target,
        step,
        max_iterations: int("bones.wrap.max_iterations", w.max_iterations, 1, 65535)?,
        split_tolerance: fx("bones.wrap.split_tolerance", w.split_tolerance, 0.001, 1.0)?,
        weights: w.weights,
        target_max,
        step_max,
    };
    Ok(Checked::Bones {
        grammar,
        wrap,
        frames,
    })
}

/// A number within `lo..=hi`, or a range `[a, b]` of them with a ≤ b (the
/// bones paper's random parameter values, Summary and Fig. 3): the number
/// or a, and b when it is a range wider than 0 (a range of width 0 is the
/// number).
fn drawn(key: &str, v: &schema::Drawn, lo: f64, hi: f64) -> Result<(Fx, Option<Fx>)> {
    match v {
        schema::Drawn::Number(v) => Ok((fx(key, *v, lo, hi)?, None)),
        schema::Drawn::Range(ends) => {
            let [a, b] = ends[..] else {
                return invalid(
                    key,
                    format!(
                        "a range has 2 numbers [lo, hi], this one {} (allowed: a number from {lo} to {hi}, or [lo, hi] within it)",
                        ends.len()
                    ),
                );
            };
            let (a_fx, b_fx) = (
                fx(&format!("{key}[0]"), a, lo, hi)?,
                fx(&format!("{key}[1]"), b, lo, hi)?,
            );
            if a > b {
                return invalid(
                    key,
                    format!(
                        "[{}, {}]: the low end is above the high end (allowed: [lo, hi] with lo <= hi, within {lo} to {hi})",
                        shown(a),
                        shown(b)
                    ),
                );
            }
            Ok((a_fx, (b_fx != a_fx).then_some(b_fx)))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Scenario;

    /// What hand-written Rust parameters rely on (`docs/embedding.md`):
    /// the core's `Fx::from_ratio` of a decimal's digits over its power of
    /// ten is the value this reader gives the decimal, and
    /// `horn::Percent(p).ratio()` the ratio it gives `p` %; a tie (an odd
    /// multiple of 2⁻¹⁷, exact in f64) goes away from zero in both.
    #[test]
    fn from_ratio_rounds_decimals_as_the_reader() {
        // A deterministic spread of numerators over the whole range.
        let mut n: u64 = 0x9e37_79b9_7f4a_7c15;
        for places in 0..=9u32 {
            let den = 10i64.pow(places);
            for i in 0..20_000i64 {
                n = n
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                let limit = (32_767 * den).min(i64::from(i32::MAX));
                let num = if i < 1_000 {
                    i - 500
                } else {
                    (n >> 33) as i64 % (2 * limit + 1) - limit
                };
                let text = format!(
                    "{}{}.{:0width$}",
                    if num < 0 { "-" } else { "" },
                    num.abs() / den,
                    num.abs() % den,
                    width = places as usize
                );
                let read = crate::value::fx("v", text.parse().unwrap(), -32768.0, 32768.0).unwrap();
                let ratio = Fx::from_ratio(num as i32, den as i32);
                assert_eq!(read, ratio, "{text} = {num}/{den}");
            }
        }
        for k in -1000..1000i32 {
            let tie = f64::from(2 * k + 1) / 131_072.0;
            let read = crate::value::fx("v", tie, -1.0, 1.0).unwrap();
            assert_eq!(read, Fx::from_ratio(2 * k + 1, 131_072), "{tie}");
        }
        for p in 1..=10_000u16 {
            let read = percent("p", f64::from(p), 0.01, 10_000.0).unwrap();
            assert_eq!(read, morphogen::horn::Percent(p).ratio(), "{p} %");
        }
    }

    /// The yearling of `docs/scenarios.md`, its head width given as `head`.
    fn yearling(head: &str) -> std::result::Result<Scenario, crate::Error> {
        Scenario::from_text(
            "yearling",
            &format!(
                r#"name = "yearling"
summary = "a quarter horse from birth to 12 months"
seed = 0
[body]
model = "horse"
frames = 2
first_age = 0
last_age = 12
[body.table]
unit = "in"
interpolation = "linear"
ages = [0, 12]
columns = [
    {{ name = "elbow-to-ground", values = [25, 33.1] }},
    {{ name = "cannon-diameter", values = [1.43, 2.19] }},
    {{ name = "hind-leg", values = [18.1, 22.8] }},
    {{ name = "head-width", {head} }},
]
"#
            ),
        )
    }

    fn head_width(s: &Scenario) -> Vec<Fx> {
        let Checked::Body { columns, .. } = s.checked() else {
            panic!("a body")
        };
        columns[3].1.clone()
    }

    /// A girth of a circle is π diameters; of an ellipse whose axes are in
    /// the ratio 2, π·√(5/8) major diameters (growth paper Sec. 6).
    #[test]
    fn girths_become_major_diameters() {
        let pi = std::f64::consts::PI;
        let circle =
            yearling(&format!("values = [{}, {}], girth = 1", 5.6 * pi, 7.8 * pi)).unwrap();
        let diameters = yearling("values = [5.6, 7.8]").unwrap();
        let (a, b) = (head_width(&circle), head_width(&diameters));
        for (a, b) in a.iter().zip(&b) {
            assert!((a.to_bits() - b.to_bits()).abs() <= 1, "{a:?} {b:?}");
        }
        let k = pi * (5.0f64 / 8.0).sqrt();
        let ellipse = yearling(&format!("values = [{}, {}], girth = 2", 5.6 * k, 7.8 * k)).unwrap();
        for (a, b) in head_width(&ellipse).iter().zip(&b) {
            assert!((a.to_bits() - b.to_bits()).abs() <= 1, "{a:?} {b:?}");
        }
        let err = yearling("values = [5.6, 7.8], girth = 0.5")
            .unwrap_err()
            .to_string();
        assert!(err.contains("body.table.columns[3].girth"), "{err}");
    }

    /// A run made shorter than its frames says which day it ends on.
    #[test]
    fn frames_past_the_last_day_name_it() {
        let croton = crate::builtin("croton").unwrap();
        let set = |key: &str, value: &str| {
            croton
                .clone_with_sets(&[(key.into(), value.into())])
                .map(|_| ())
                .map_err(|e| e.to_string())
        };
        let err = set("mosaic.days", "1").unwrap_err();
        assert!(
            err.ends_with(
                "mosaic.frames[1]: day 10 is past the run's last day, mosaic.days = 1 \
                 (allowed: 0 to mosaic.days, or \"every-day\")"
            ),
            "{err}"
        );
        let err = set("mosaic.frames", "[0, 5, 5]").unwrap_err();
        assert!(
            err.ends_with(
                "mosaic.frames[2]: days must increase (allowed: 0 to mosaic.days, increasing)"
            ),
            "{err}"
        );
        let err = set("mosaic.frames", "[0, 4097]").unwrap_err();
        assert!(
            err.ends_with("mosaic.frames[1]: 4097 is out of range (allowed: 0 to 35)"),
            "{err}"
        );
    }

    fn f(v: Fx) -> f64 {
        f64::from(v.to_bits()) / 65_536.0
    }

    /// Shoelace area of a closed polygon.
    fn area(points: &[[Fx; 2]]) -> f64 {
        let n = points.len();
        (0..n)
            .map(|i| {
                let ([y0, z0], [y1, z1]) = (points[i], points[(i + 1) % n]);
                f(y0) * f(z1) - f(y1) * f(z0)
            })
            .sum::<f64>()
            / 2.0
    }

    /// Triangularity 0 is the circle, 1 the equilateral triangle of the
    /// same area, corner up, flat side down; both counter-clockwise.
    #[test]
    fn horn_sections_run_from_circle_to_triangle() {
        let r = Fx::from_int(3);
        let circle = horn_section(r, Fx::ZERO);
        assert_eq!(circle.len(), SECTION_POINTS as usize);
        for [y, z] in &circle {
            assert!(((f(*y).powi(2) + f(*z).powi(2)).sqrt() - 3.0).abs() < 1e-3);
        }
        let triangle = horn_section(r, Fx::ONE);
        let inradius = 3.0 * (std::f64::consts::PI / (3.0 * 3f64.sqrt())).sqrt();
        assert!(
            (f(triangle[0][1]) - 2.0 * inradius).abs() < 1e-3,
            "the top corner"
        );
        assert!(f(triangle[0][0]).abs() < 1e-3);
        let bottom = &triangle[SECTION_POINTS as usize / 2];
        assert!(
            (f(bottom[1]) + inradius).abs() < 1e-3,
            "the bottom side, flat"
        );
        let disc = std::f64::consts::PI * 9.0;
        // Sixty points cut the circle's area by 0.2 %; the triangle's
        // corners are points, so its area is exact.
        assert!(
            (area(&circle) / disc - 1.0).abs() < 3e-3,
            "{}",
            area(&circle)
        );
        assert!(
            (area(&triangle) / disc - 1.0).abs() < 1e-3,
            "{}",
            area(&triangle)
        );
        let between = horn_section(r, Fx::HALF);
        assert!(area(&between) > 0.0);
    }
}

#[cfg(test)]
mod input_tests {
    use crate::{Checked, Scenario, builtin, inline_value};

    /// The speckled mosaic of `docs/scenarios.md` with `types`' initial
    /// probabilities and the mutation matrix `mutation`.
    fn speckled(b: f64, f: f64, mutation: &str) -> Result<Scenario, crate::Error> {
        Scenario::from_text(
            "speckled.toml",
            &format!(
                r#"name = "speckled"
seed = 1
[mosaic]
domain = {{ size = [20, 20], periodic = [true, true] }}
initial_cells = 40
days = 2
radius_weight = 1
push_weight = 0.066
initial_relaxations = 4
daily_relaxations = 2
frames = [0, 2]
adhesion = [[0.8, 0, 0], [0, 0.5, 0], [0, 0, 0.5]]
mutation = {mutation}
[[mosaic.types]]
name = "B"
colour = [40, 105, 45]
division_days = 10
initial_probability = {b}
[[mosaic.types]]
name = "F"
colour = [236, 200, 48]
division_days = 4
initial_probability = {f}
[[mosaic.types]]
colour = [200, 40, 40]
division_days = 4
initial_probability = 0
"#
            ),
        )
    }

    const NO_MUTATION: &str = "[[0, 0, 0], [0, 0, 0.2], [0, 0, 0]]";

    #[test]
    fn initial_probabilities_summing_past_one_are_refused_with_their_sum() {
        let e = speckled(0.9, 0.3, NO_MUTATION).unwrap_err();
        assert_eq!(e.key, "mosaic.types[1].initial_probability");
        assert!(
            e.to_string().starts_with(
                "speckled.toml:23: mosaic.types[1].initial_probability: the initial probabilities sum to 1.2 (B 0.9 + F 0.3 + type 2 0), past 1"
            ),
            "{e}"
        );
        // Decimals that sum to 1, and a sum that leaves type 0 a share.
        speckled(0.7, 0.3, NO_MUTATION).unwrap();
        speckled(0.1, 0.2, NO_MUTATION).unwrap();
        speckled(0.3, 0.7, NO_MUTATION).unwrap();
    }

    #[test]
    fn a_mutation_row_past_one_or_a_diagonal_is_refused() {
        let e = speckled(0.7, 0.3, "[[0, 0.9, 0.9], [0, 0, 0], [0, 0, 0]]").unwrap_err();
        assert_eq!(e.key, "mosaic.mutation[0]");
        assert!(
            e.message.starts_with(
                "a child of B mutates with probabilities summing to 1.8 (F 0.9 + type 2 0.9), past 1"
            ),
            "{e}"
        );
        let e = speckled(0.7, 0.3, "[[0, 0, 0], [0, 0.8, 0.2], [0, 0, 0]]").unwrap_err();
        assert_eq!(e.key, "mosaic.mutation[1][1]");
        assert!(
            e.message
                .contains("the diagonal is the probability of not mutating (a child of F keeping its type), 1 minus the rest of the row, and is implied"),
            "{e}"
        );
        speckled(0.7, 0.3, "[[0, 0.5, 0.5], [0, 0, 0.2], [0, 0, 0]]").unwrap();
    }

    #[test]
    fn a_bone_grammar_cannot_set_plant_settings() {
        let bone = builtin("long-bone").expect("preset");
        for (setting, value) in [("plants", "2"), ("spacing", "10"), ("animate", "1")] {
            let text = format!("n = 1\n{setting} = {value}\naxiom: F\n");
            let grammar = inline_value("bones.grammar", "mine.lsys", text.into_bytes()).unwrap();
            let e = bone
                .clone_with_sets(&[("bones.grammar".into(), grammar)])
                .unwrap_err();
            assert_eq!(e.key, "bones.grammar");
            assert_eq!(
                e.message,
                format!(
                    "mine.lsys:2: `{setting}` applies only to L-system plant presets ([lsystem]); a bone's skeleton is one derivation wrapped once, so remove it"
                )
            );
        }
    }

    fn grammar_text(s: &Scenario) -> &str {
        match s.checked() {
            Checked::LSystem(text) => text,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn grammar_constants_are_set_as_lsystem_keys() {
        let shrub = builtin("abop-shrub").expect("preset");
        let file = include_str!("../../grammars/abop-shrub.lsys");
        let set = |k: &str, v: &str| shrub.clone_with_sets(&[(k.into(), v.into())]);
        // The grammar that runs is the file edited by hand.
        let delta = set("lsystem.delta", "30").unwrap();
        assert_eq!(
            grammar_text(&delta),
            file.replace("delta = 22.5", "delta = 30")
        );
        assert_eq!(grammar_text(&shrub), file);
        let n = set("lsystem.n", "3").unwrap();
        assert_eq!(grammar_text(&n), file.replace("n = 7", "n = 3"));
        let e = set("lsystem.detla", "30").unwrap_err();
        assert_eq!(
            e.to_string().split(": ../").next().unwrap(),
            "--set lsystem.detla=30: lsystem.detla: unknown setting or constant (did you mean `delta`?)"
        );
        let e = set("lsystem.n", "300").unwrap_err();
        assert!(e.message.starts_with("300 is out of range"), "{e}");
        // A scenario file's `[lsystem]` table does the same.
        let toml = format!(
            "name = \"shrub-30\"\n[lsystem]\ngrammar = {{ text = {} }}\ndelta = 30\n",
            toml::Value::String(file.into())
        );
        let from_file = Scenario::from_text("shrub-30.toml", &toml).unwrap();
        assert_eq!(grammar_text(&from_file), grammar_text(&delta));
        // Every constant of the grammar is a control.
        let keys: Vec<String> = shrub.ranges().into_iter().map(|r| r.key).collect();
        assert_eq!(
            keys,
            [
                "lsystem.n",
                "lsystem.delta",
                "lsystem.step",
                "lsystem.width",
                "lsystem.thin"
            ]
        );
    }

    #[test]
    fn grammar_constants_are_set_as_bones_keys() {
        let bone = builtin("long-bone").expect("preset");
        let file = include_str!("../../grammars/long-bone.lsys");
        let set = |k: &str, v: &str| bone.clone_with_sets(&[(k.into(), v.into())]);
        let skeleton = |s: &Scenario| match s.checked() {
            Checked::Bones { grammar, .. } => grammar.clone(),
            other => panic!("{other:?}"),
        };
        assert_eq!(
            skeleton(&set("bones.n", "6").unwrap()),
            file.replace("n = 12", "n = 6")
        );
        let e = set("bones.m", "6").unwrap_err();
        assert!(
            e.to_string().starts_with(
                "--set bones.m=6: bones.m: unknown setting or constant (did you mean `n`?)"
            ),
            "{e}"
        );
        let e = set("bones.plants", "2").unwrap_err();
        assert_eq!(e.key, "bones.plants");
        assert!(
            e.message
                .starts_with("`plants` applies only to L-system plant presets"),
            "{e}"
        );
        let keys: Vec<String> = bone.ranges().into_iter().map(|r| r.key).collect();
        assert!(keys.contains(&"bones.n".to_string()), "{keys:?}");
    }
}

#[cfg(test)]
mod wrap_range_tests {
    use crate::Scenario;

    /// `long-bone-random` with `key` set to `value`.
    fn random_bone(key: &str, value: &str) -> std::result::Result<Scenario, String> {
        crate::builtin("long-bone-random")
            .unwrap()
            .clone_with_sets(&[(key.into(), value.into())])
            .map_err(|e| e.to_string())
    }

    /// The parameter digest and the records after the header of a
    /// scenario's stream (seed 1).
    fn digest_and_stream(s: &Scenario) -> (u64, Vec<u8>) {
        let mut encoder = morphogen::stream::Encoder::new(Vec::new());
        s.with_preset(|p| crate::run::run(p, 1, &mut encoder, &mut |_| {}))
            .unwrap();
        let bytes = encoder.into_writer();
        let header = morphogen::stream::Decoder::new(&bytes).next().unwrap();
        let records = bytes[header.offset + header.len..].to_vec();
        (s.with_preset(|p| p.model.params_digest()), records)
    }

    /// A range for V0 or ΔV is checked at the door: two numbers, low end
    /// first, both within the key's own range; the errors name the key
    /// and the limit.
    #[test]
    fn wrap_ranges_are_checked() {
        let err = random_bone("bones.wrap.target", "[3.7, 3.1]").unwrap_err();
        assert!(
            err.ends_with(
                "bones.wrap.target: [3.7, 3.1]: the low end is above the high end \
                 (allowed: [lo, hi] with lo <= hi, within 0.01 to 1000)"
            ),
            "{err}"
        );
        let err = random_bone("bones.wrap.target", "[3, 2000]").unwrap_err();
        assert!(
            err.ends_with("bones.wrap.target[1]: 2000 is out of range (allowed: 0.01 to 1000)"),
            "{err}"
        );
        let err = random_bone("bones.wrap.step", "[0, 0.2]").unwrap_err();
        assert!(
            err.ends_with("bones.wrap.step[0]: 0 is out of range (allowed: 0.0001 to 1000)"),
            "{err}"
        );
        let err = random_bone("bones.wrap.step", "[0.1, 0.2, 0.3]").unwrap_err();
        assert!(
            err.ends_with(
                "bones.wrap.step: a range has 2 numbers [lo, hi], this one 3 \
                 (allowed: a number from 0.0001 to 1000, or [lo, hi] within it)"
            ),
            "{err}"
        );
        let ranged = random_bone("bones.wrap.step", "[0.1, 0.2]").unwrap();
        ranged.with_preset(|p| {
            let morphogen::preset::Model::Bones(b) = p.model else {
                unreachable!("a bone")
            };
            assert_eq!(
                (b.wrap.step, b.wrap.step_max),
                (
                    morphogen::fx::Fx::from_bits(6554),
                    Some(morphogen::fx::Fx::from_bits(13107))
                )
            );
        });
    }

    /// A number keeps the digest and the stream of before ranges existed
    /// (`long-bone` is pinned by its fixture; here its digest is the one
    /// the number's encoding alone gives), and a range of width 0 is that
    /// number: the same digest and the same bytes.
    #[test]
    fn a_wrap_range_of_width_0_is_the_number() {
        let plain = random_bone("bones.wrap.target", "3.4").unwrap();
        let narrow = random_bone("bones.wrap.target", "[3.4, 3.4]").unwrap();
        let wide = random_bone("bones.wrap.target", "[3.3, 3.5]").unwrap();
        let (plain, narrow, wide) = (
            digest_and_stream(&plain),
            digest_and_stream(&narrow),
            digest_and_stream(&wide),
        );
        assert_eq!(plain, narrow);
        assert_ne!(plain.0, wide.0);
        assert_ne!(plain.1, wide.1);
        // The digest of a plain wrap is the one before ranges: the fixture
        // long-bone-random had with V0 = 3.4.
        assert_eq!(plain.0, 0x29a6_a476_1bc0_6b94);
    }
}
