//! The shrinkwrap iteration (bones paper, Secs. 5–6), with three
//! corrections that make it converge in fixed point:
//!
//! - a vertex moves towards the new level V0 from where it *is*:
//!   r ← r + (V0 − V(r))·∇V/(∇V·∇V), which is the paper's eq. (12),
//!   ΔV·∇V/(∇V·∇V), when V(r) is exactly the old level, but does not
//!   accumulate the first-order error step after step;
//! - a move is at most a tenth of the initial radius, so a vertex where ∇V
//!   nearly vanishes cannot jump across the skeleton;
//! - only an edge whose two ends are on the level is split: while vertices
//!   still lag behind a rising level, splitting their edges would only add
//!   vertices where the surface is not yet (it filled a 1 200-vertex mesh
//!   with a single rod).
//!
//! The run ends after the level reaches the target: a few passes of the
//! same move at the target, each followed by a split pass, until no edge is
//! split. The iteration count is capped ([`WrapParams::max_iterations`]),
//! and so is the mesh; both are errors naming the limit.

use heapless::Vec;
use nalgebra::Vector3;
use serde::Serialize;

use crate::Error;
use crate::fx::{Fx, Real};

use super::ShrinkwrapError;
use super::element::Element;
use super::field::{FieldReal, PREPARED_ELEMENTS, PreparedElement, SkeletonField};
use super::mesh::{Mesh, VertexId};
use super::vertices::{MAX_VERTICES, Weights, collect_vertices, vertices_hold};

/// The shrinkwrap parameters of a run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct WrapParams {
    /// m: meridians of the initial sphere, a multiple of 4.
    pub meridians: u8,
    /// p: parallels of the initial sphere, odd.
    pub parallels: u8,
    /// V_target: the final level V0.
    pub target: Fx,
    /// ΔV: the level step of one iteration.
    pub step: Fx,
    /// The most level steps and final passes together.
    pub max_iterations: u16,
    /// |V − V0| / V0 beyond which an edge midpoint is split, and within
    /// which a vertex is on the level (the paper's 5 %:
    /// [`SPLIT_TOLERANCE`]). Left out of the parameter digest at the
    /// paper's value, so that the digests of runs made before it was a
    /// parameter stay the same.
    #[serde(skip_serializing_if = "WrapParams::is_paper_split")]
    pub split_tolerance: Fx,
    /// The terms of V: the paper's normalised weights over the skeleton's
    /// vertices (eqs. (1)–(2)), or each element's constant ρ (Sec. 6).
    /// Left out of the parameter digest when constant, the only form
    /// before it was a parameter.
    #[serde(skip_serializing_if = "Weights::is_constant")]
    pub weights: Weights,
    /// The top of V0's range, from `target` to this, in which a run of
    /// several wraps (a bone's frames, [`crate::bones::BonesParams::frame_wrap`])
    /// draws each wrap's V0 uniformly (bones paper, Summary: "a
    /// possibility of using random parameters values"; Fig. 3). `None`: V0
    /// is `target`. [`Shrinkwrap::start`] wraps at `target` whatever this
    /// is. Left out of the parameter digest when `None`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub target_max: Option<Fx>,
    /// The top of ΔV's range, from `step` to this, drawn as
    /// [`target_max`](WrapParams::target_max)'s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_max: Option<Fx>,
}

impl WrapParams {
    fn is_paper_split(split: &Fx) -> bool {
        *split == SPLIT_TOLERANCE
    }
}

/// The paper's split tolerance, |V − V0| / V0 = 5 % (Sec. 5).
pub const SPLIT_TOLERANCE: Fx = Fx::from_ratio(1, 20);
/// Passes at the target level without a split that end the run.
const FINAL_PASSES: u8 = 4;
/// Newton moves that put a new midpoint vertex on the surface.
const MIDPOINT_MOVES: u8 = 3;
/// Newton moves, at most, that take the initial sphere to the mean level.
const MEAN_MOVES: u8 = 16;

/// Where a run is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Phase {
    /// Not started.
    Idle,
    /// Raising the level by ΔV per iteration.
    Rising,
    /// At the target: settling and splitting until no edge is split.
    Settling {
        /// Passes left.
        passes: u8,
    },
    /// Finished: every vertex is on the target surface.
    Done,
}

/// A shrinkwrap run around a skeleton of elements, with a mesh of at most
/// `V` vertices and `T` triangles, keeping the field at up to `C` vertices
/// from one move to the next (0, the default, on an MCU).
#[derive(Debug)]
pub struct Shrinkwrap<R: Real, const V: usize, const T: usize, const C: usize = 0> {
    mesh: Mesh<R, V, T>,
    level: R,
    target: R,
    step: R,
    max_move: R,
    iterations: u16,
    max_iterations: u16,
    /// [`WrapParams::split_tolerance`].
    split: R,
    phase: Phase,
    /// Per vertex: whether it is on the current level (within
    /// the split tolerance) after the last move.
    on_level: Vec<bool, V>,
    /// The skeleton in the form [`WrapParams::weights`] evaluates it in.
    kernel: Kernel<R>,
    /// V and ∇V where the last move left each of the first vertices.
    cache: FieldCache<R, C>,
}

/// V and ∇V at the first `C` vertices where the last move left them: the
/// level check after a move evaluates the field there, and the next move
/// starts from the same place, so one evaluation (with the gradient) serves
/// both instead of a potential and then the field again (a third of a bone's
/// field evaluations). Valid for vertices below its length while the
/// skeleton stays the same (`Shrinkwrap::iterate` checks); the results are
/// those of evaluating again, bit for bit.
/// 16 B per vertex for `Fx`: for a host; an MCU keeps `C` = 0.
#[derive(Debug)]
struct FieldCache<R: Real, const C: usize> {
    at: Vec<(R, Vector3<R>), C>,
}

impl<R: FieldReal, const C: usize> FieldCache<R, C> {
    /// The field at vertex `i` at `r`, from the cache or evaluated.
    fn field(&self, field: &SkeletonField<'_, R>, i: usize, r: &Vector3<R>) -> (R, Vector3<R>) {
        match self.at.get(i) {
            Some(&known) if C > 0 => known,
            _ => field.at(r),
        }
    }

    /// V at vertex `i`, just moved to `r`: with the gradient kept for
    /// the next move when the cache has room for it (vertex `i` follows
    /// the ones kept, as `move_all` visits them in order), else alone.
    fn level_after_move(&mut self, field: &SkeletonField<'_, R>, i: usize, r: &Vector3<R>) -> R {
        if C == 0 || i > self.at.len() || i >= C {
            return field.potential_at(r);
        }
        let known = field.at(r);
        match self.at.get_mut(i) {
            Some(slot) => *slot = known,
            // i == len < C: room for it.
            None => {
                let _ = self.at.push(known);
            }
        }
        known.0
    }
}

/// The centroid of the element ends and the largest distance of an end
/// from it.
fn bounds<R: Real>(elements: &[Element<R>]) -> (Vector3<R>, R) {
    let mut sum = [R::Wide::default(); 3];
    for e in elements {
        for p in [e.a, e.b] {
            for k in 0..3 {
                sum[k] = R::widen(sum[k], p[k]);
            }
        }
    }
    let n = R::from_int(2 * elements.len() as i32);
    let centre = Vector3::from(sum.map(|s| R::narrow(s).div(n)));
    let mut far = R::zero();
    for e in elements {
        for p in [e.a, e.b] {
            let d = R::norm(&(Vector3::from(p) - centre));
            if d > far {
                far = d;
            }
        }
    }
    (centre, far)
}

/// The skeleton in the kernel's form, made once per pass: its elements
/// prepared (constant weights, Sec. 6) or its distinct vertices (the
/// paper's weights, eqs. (1)–(2)). One or the other, so that a bone's
/// runner holds the larger of the two and not both (on a Cortex-M0+ both
/// left the stack too little RAM).
#[derive(Debug)]
#[allow(
    clippy::large_enum_variant,
    reason = "the variants share their storage on purpose: boxing needs an allocator"
)]
enum Kernel<R> {
    /// With [`Weights::Constant`].
    Prepared(Vec<PreparedElement, PREPARED_ELEMENTS>),
    /// With [`Weights::Normalised`].
    Vertices(Vec<[R; 3], MAX_VERTICES>),
}

impl<R: FieldReal> Kernel<R> {
    /// Empty, for `weights`, reusing `self` when it is of that form.
    fn reset(&mut self, weights: Weights) {
        match (weights, &mut *self) {
            (Weights::Constant, Kernel::Prepared(prepared)) => prepared.clear(),
            (Weights::Normalised, Kernel::Vertices(vertices)) => vertices.clear(),
            (Weights::Constant, kernel) => *kernel = Kernel::Prepared(Vec::new()),
            (Weights::Normalised, kernel) => *kernel = Kernel::Vertices(Vec::new()),
        }
    }

    /// Whether this holds the skeleton `elements` as it is.
    fn holds(&self, elements: &[Element<R>]) -> bool {
        match self {
            Kernel::Prepared(prepared) => SkeletonField::holds(elements, prepared),
            Kernel::Vertices(vertices) => vertices_hold(elements, vertices),
        }
    }

    /// The field of `elements`, made in this kernel's form.
    ///
    /// # Errors
    /// More distinct vertices than [`MAX_VERTICES`].
    fn field<'f>(&'f mut self, elements: &'f [Element<R>]) -> Result<SkeletonField<'f, R>, Error> {
        Ok(match self {
            Kernel::Prepared(prepared) => SkeletonField::new(elements, prepared),
            Kernel::Vertices(vertices) => {
                collect_vertices(elements, vertices)?;
                SkeletonField::normalised(elements, vertices)
            }
        })
    }
}

/// r moved towards the level `level` along ∇V, by at most `max_move`.
fn toward<R: FieldReal>(
    field: &SkeletonField<'_, R>,
    r: &Vector3<R>,
    level: R,
    max_move: R,
) -> Vector3<R> {
    toward_from(field.at(r), r, level, max_move)
}

/// r, where the field is `(v, g)`, moved towards the level `level` along
/// ∇V, by at most `max_move`.
fn toward_from<R: FieldReal>(
    (v, g): (R, Vector3<R>),
    r: &Vector3<R>,
    level: R,
    max_move: R,
) -> Vector3<R> {
    let norm = R::norm(&g);
    if norm <= R::zero() {
        return *r;
    }
    let unit = g.map(|c| c.div(norm));
    let mut distance = (level - v).div(norm);
    if distance > max_move {
        distance = max_move;
    } else if distance < -max_move {
        distance = -max_move;
    }
    r + unit * distance
}

/// Whether V at `r` is off `level` by more than `split` (relative).
fn off<R: FieldReal>(field: &SkeletonField<'_, R>, r: &Vector3<R>, level: R, split: R) -> bool {
    off_level(field.potential_at(r), level, split)
}

/// Whether `v` is off `level` by more than `split` (relative).
fn off_level<R: FieldReal>(v: R, level: R, split: R) -> bool {
    (v - level).abs() > level * split
}

impl<R: FieldReal, const V: usize, const T: usize, const C: usize> Shrinkwrap<R, V, T, C> {
    /// An idle run (`const`, for a `static`).
    #[must_use]
    pub const fn new(zero: R) -> Shrinkwrap<R, V, T, C> {
        Shrinkwrap {
            mesh: Mesh::new(),
            level: zero,
            target: zero,
            step: zero,
            max_move: zero,
            iterations: 0,
            max_iterations: 0,
            split: zero,
            phase: Phase::Idle,
            on_level: Vec::new(),
            kernel: Kernel::Prepared(Vec::new()),
            cache: FieldCache { at: Vec::new() },
        }
    }

    /// The mesh.
    #[must_use]
    pub fn mesh(&self) -> &Mesh<R, V, T> {
        &self.mesh
    }

    /// The current level V0.
    #[must_use]
    pub fn level(&self) -> R {
        self.level
    }

    /// Iterations so far.
    #[must_use]
    pub fn iterations(&self) -> u16 {
        self.iterations
    }

    /// Where the run is.
    #[must_use]
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// Starts a run: the sphere around the skeleton's centroid with radius
    /// 1.3 × its farthest point, every vertex moved to the mean V.
    ///
    /// # Errors
    /// No elements, a non-positive target or step, a bad sphere, or a
    /// capacity.
    pub fn start(&mut self, elements: &[Element<R>], params: &WrapParams) -> Result<(), Error> {
        self.phase = Phase::Idle;
        if elements.is_empty() {
            return Err(ShrinkwrapError::NoSkeleton.into());
        }
        if params.target <= Fx::ZERO || params.step <= Fx::ZERO {
            return Err(ShrinkwrapError::Level.into());
        }
        let (centre, far) = bounds(elements);
        // A skeleton of one point: the sphere of that point alone.
        let far = if far > R::zero() {
            far
        } else {
            let strength = match params.weights {
                Weights::Normalised => R::one(),
                Weights::Constant => elements[0].weight,
            };
            strength.div(R::from_fx(params.target))
        };
        let radius = far * R::from_ratio(13, 10);
        self.mesh
            .sphere(centre, radius, params.meridians, params.parallels)?;
        self.target = R::from_fx(params.target);
        self.step = R::from_fx(params.step);
        self.max_move = radius * R::from_ratio(1, 10);
        self.iterations = 0;
        self.max_iterations = params.max_iterations;
        self.split = R::from_fx(params.split_tolerance);
        self.cache.at.clear();
        self.kernel.reset(params.weights);
        let field = self.kernel.field(elements)?;
        let mut sum = R::Wide::default();
        for r in self.mesh.vertices() {
            sum = R::widen(sum, field.potential_at(r));
        }
        let mean = R::narrow(sum).div(R::from_int(self.mesh.vertices().len() as i32));
        self.level = if mean < self.target {
            mean
        } else {
            self.target
        };
        for _ in 0..MEAN_MOVES {
            if move_all(
                &mut self.mesh,
                &mut self.on_level,
                &mut self.cache,
                &field,
                self.level,
                self.max_move,
                self.split,
            ) == 0
            {
                break;
            }
        }
        self.phase = Phase::Rising;
        Ok(())
    }

    /// One iteration: raise the level by ΔV (or, at the target, settle),
    /// move every vertex, split the edges whose midpoint is off.
    ///
    /// # Errors
    /// [`WrapParams::max_iterations`] or a mesh capacity exceeded.
    pub fn iterate(&mut self, elements: &[Element<R>]) -> Result<Phase, Error> {
        match self.phase {
            Phase::Idle | Phase::Done => return Ok(self.phase),
            Phase::Rising | Phase::Settling { .. } => {}
        }
        if self.iterations >= self.max_iterations {
            return Err(Error::Capacity {
                limit: "shrinkwrap iterations (WrapParams::max_iterations)",
                capacity: self.max_iterations as u32,
            });
        }
        self.iterations += 1;
        if self.phase == Phase::Rising {
            self.level += self.step;
            if self.level >= self.target {
                self.level = self.target;
                self.phase = Phase::Settling {
                    passes: FINAL_PASSES,
                };
            }
        }
        let (level, max_move, tolerance) = (self.level, self.max_move, self.split);
        // The cached field holds for the skeleton it was computed for.
        if C > 0 && !self.kernel.holds(elements) {
            self.cache.at.clear();
        }
        let field = self.kernel.field(elements)?;
        move_all(
            &mut self.mesh,
            &mut self.on_level,
            &mut self.cache,
            &field,
            level,
            max_move,
            tolerance,
        );
        let on_level = &self.on_level;
        let split = self.mesh.refine(|a, pa, b, pb| {
            // An edge off the surface because its ends are is left to the
            // moves; only one whose ends are on it is split.
            let settled = |v: VertexId| on_level.get(v as usize).copied().unwrap_or(false);
            if !settled(a) || !settled(b) {
                return None;
            }
            let mid = Vector3::new(
                pa.x.midpoint(pb.x),
                pa.y.midpoint(pb.y),
                pa.z.midpoint(pb.z),
            );
            off(&field, &mid, level, tolerance).then(|| {
                let mut r = mid;
                for _ in 0..MIDPOINT_MOVES {
                    r = toward(&field, &r, level, max_move);
                }
                r
            })
        })?;
        if let Phase::Settling { passes } = self.phase {
            self.phase = if split == 0 || passes <= 1 {
                Phase::Done
            } else {
                Phase::Settling { passes: passes - 1 }
            };
        }
        Ok(self.phase)
    }

    /// Runs [`Shrinkwrap::start`] and iterates to the end.
    ///
    /// # Errors
    /// As [`Shrinkwrap::start`] and [`Shrinkwrap::iterate`].
    pub fn run(&mut self, elements: &[Element<R>], params: &WrapParams) -> Result<(), Error> {
        self.start(elements, params)?;
        while self.iterate(elements)? != Phase::Done {}
        Ok(())
    }
}

/// Moves every vertex of `mesh` towards `level` and flags in `on_level`
/// whether it is on it afterwards (within `split`); returns how many are
/// not.
fn move_all<R: FieldReal, const V: usize, const T: usize, const C: usize>(
    mesh: &mut Mesh<R, V, T>,
    on_level: &mut Vec<bool, V>,
    cache: &mut FieldCache<R, C>,
    field: &SkeletonField<'_, R>,
    level: R,
    max_move: R,
    split: R,
) -> usize {
    on_level.clear();
    for (i, r) in mesh.vertices_mut().iter_mut().enumerate() {
        *r = toward_from(cache.field(field, i, r), r, level, max_move);
        let v = cache.level_after_move(field, i, r);
        // As many flags as vertices: this cannot fail.
        let _ = on_level.push(!off_level(v, level, split));
    }
    on_level.iter().filter(|&&on| !on).count()
}

/// The largest |V(r) − V0| / V0 over `points` (a quality measure), V
/// with `weights`; zero for a skeleton of more than [`MAX_VERTICES`]
/// vertices with the paper's weights.
#[must_use]
pub fn worst_level_error<R: FieldReal>(
    elements: &[Element<R>],
    weights: Weights,
    points: &[Vector3<R>],
    level: R,
) -> R {
    let mut kernel = Kernel::Prepared(Vec::new());
    kernel.reset(weights);
    let Ok(field) = kernel.field(elements) else {
        return R::zero();
    };
    let mut worst = R::zero();
    for r in points {
        let e = (field.potential_at(r) - level).abs().div(level);
        if e > worst {
            worst = e;
        }
    }
    worst
}
