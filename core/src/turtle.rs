//! The 3D turtle that draws an L-system's string (ABOP ch. 1.5; Digital
//! Design of Nature, Sec. 5.4, "Three-dimensional commands"), generic over
//! [`Real`] so the fixed-point turtle can be checked against an `f64` one.
//!
//! # Conventions (pinned; `docs/lsystems.md` has the figures)
//!
//! World: x right, y up (against gravity), z towards the viewer. The
//! turtle starts at the origin with heading H = +y, left L = −x, up U = +z
//! (so H × L = U), width `width`, colour 0. Every turn is a right-handed
//! rotation of the frame by δ (or the module's parameter, in degrees)
//! about one of the turtle's own axes:
//!
//! | symbol | rotation | effect |
//! |---|---|---|
//! | `+` / `-` | about U by +δ / −δ | turn left (H towards L) / right |
//! | `&` / `^` | about L by +δ / −δ | pitch down (H towards −U) / up |
//! | `\` / `/` | about H by +δ / −δ | roll (L towards U) / back |
//! | `\|` | about U by 180° | turn around |
//! | `$` | roll about H | L horizontal: L = (V × H)/‖V × H‖, U = H × L, V = +y |
//!
//! So in 2D (viewed from +z) `+` turns counter-clockwise, as ABOP's 2D
//! figures have it. ABOP prints `+` as R_U(δ), `&` as R_L(δ) and `\` as
//! R_H(δ); its matrices, taken literally with row vectors, turn the other
//! way for `+` and `&`: we follow its words (turn left, pitch down), and
//! its matrix for `\`.
//!
//! Other symbols: `F`/`G` move by `step` (or the parameter) drawing a
//! segment, `f`/`g` move without drawing; inside `{ }` the end of every
//! `F`/`f` move and every `.` add a polygon vertex (`G`/`g` do not); `{`
//! adds the start position; `}` emits the polygon (a vertex equal to the
//! previous one, or a last vertex equal to the first, is dropped). `!`
//! multiplies the width by `thin` (`!(w)` sets it), `'` adds 1 to the
//! colour index (`'(c)` sets it). `[`/`]` push/pop the whole state (not the
//! polygon). Any other symbol draws nothing; the grammar parser refuses
//! the symbols that ABOP or L-Py give a meaning this turtle does not
//! implement ([`crate::lsys::UNSUPPORTED_SYMBOLS`]).

use heapless::Vec;
use nalgebra::Vector3;

use crate::fx::{Angle, Fx, Real};
use crate::lsys::module::Module;

/// Depth of the `[` stack.
pub const MAX_TURTLE_STACK: usize = 16;
/// Vertices of one polygon.
pub const MAX_POLYGON_VERTICES: usize = 24;
/// The largest coordinate the turtle may reach: half the I16F16 range, so
/// that no move can saturate unnoticed.
pub const COORDINATE_LIMIT: i32 = 16_384;

/// An error of the turtle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum TurtleError {
    /// More than `MAX_TURTLE_STACK` nested `[`.
    StackOverflow,
    /// A `]` without its `[`.
    UnmatchedPop,
    /// A `{` inside an open polygon.
    NestedPolygon,
    /// A `}` without its `{`.
    UnmatchedPolygonEnd,
    /// The string ended inside `{ }`.
    UnclosedPolygon,
    /// More than `MAX_POLYGON_VERTICES` vertices in one polygon.
    TooManyVertices,
    /// A coordinate beyond ±`COORDINATE_LIMIT`.
    OutOfRange,
    /// `!(w)` with a negative width.
    NegativeWidth,
    /// `~` naming no predefined surface (see [`SURFACES`]).
    UnknownSurface,
    /// `'(c)` with a colour index outside 0 to 65 535.
    ColourOutOfRange,
}

impl core::fmt::Display for TurtleError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            TurtleError::StackOverflow => write!(
                f,
                "capacity MAX_TURTLE_STACK = {MAX_TURTLE_STACK} exceeded (too many nested `[`)"
            ),
            TurtleError::UnmatchedPop => f.write_str("`]` without a matching `[`"),
            TurtleError::NestedPolygon => f.write_str("`{` inside an open polygon"),
            TurtleError::UnmatchedPolygonEnd => f.write_str("`}` without a matching `{`"),
            TurtleError::UnclosedPolygon => f.write_str("the string ended inside `{ }`"),
            TurtleError::TooManyVertices => write!(
                f,
                "capacity MAX_POLYGON_VERTICES = {MAX_POLYGON_VERTICES} exceeded"
            ),
            TurtleError::OutOfRange => write!(
                f,
                "the turtle left the drawable range ±COORDINATE_LIMIT = {COORDINATE_LIMIT}"
            ),
            TurtleError::NegativeWidth => f.write_str("`!(w)` with a negative width"),
            TurtleError::UnknownSurface => f.write_str("`~` naming no predefined surface"),
            TurtleError::ColourOutOfRange => {
                f.write_str("`'(c)` with a colour index outside 0 to 65535")
            }
        }
    }
}

impl core::error::Error for TurtleError {}

/// The turtle's state: position, orientation frame, width and colour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State<R: Real = Fx> {
    /// Position.
    pub position: Vector3<R>,
    /// Heading H.
    pub heading: Vector3<R>,
    /// Left L.
    pub left: Vector3<R>,
    /// Up U = H × L.
    pub up: Vector3<R>,
    /// Segment width.
    pub width: R,
    /// Colour index.
    pub colour: u16,
}

/// What one module drew.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Drawn<R: Real = Fx> {
    /// Nothing.
    Nothing,
    /// A segment from `a` to `b`.
    Segment {
        /// Start.
        a: Vector3<R>,
        /// End.
        b: Vector3<R>,
        /// Width.
        width: R,
        /// Colour index.
        colour: u16,
    },
    /// A polygon closed; its vertices are [`Turtle::polygon`].
    Polygon {
        /// Colour index.
        colour: u16,
    },
}

/// Lengths and angles the turtle uses for bare symbols.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params<R: Real = Fx> {
    /// Length of a bare move.
    pub step: R,
    /// Turn angle δ.
    pub delta: Angle,
    /// Initial width.
    pub width: R,
    /// Width factor of a bare `!`.
    pub thin: R,
    /// The tropism vector T (ABOP Sec. 2.2), in world coordinates.
    pub tropism: Vector3<R>,
    /// The susceptibility e to tropism (0: none). After each `F` or `G`
    /// the frame turns by α = e·‖H × T‖ radians about H × T.
    pub elasticity: R,
}

/// The 3D turtle with a bounded stack.
#[derive(Clone, Debug)]
pub struct Turtle<R: Real = Fx> {
    state: State<R>,
    stack: Vec<State<R>, MAX_TURTLE_STACK>,
    polygon: Vec<Vector3<R>, MAX_POLYGON_VERTICES>,
    polygon_open: bool,
    params: Params<R>,
    cos_delta: R,
    sin_delta: R,
}

// The next two are functions of their own, over separate borrows of the
// turtle's fields, so that the compiler knows that source and destination
// do not overlap: a state or a vertex is then copied in place, where inside
// a method of the whole turtle it was a call to `memmove` (and that 1.6 KB
// routine in the firmware).

/// Pops the state saved by the matching `[` into `state`.
fn restore<R: Real>(
    state: &mut State<R>,
    stack: &mut Vec<State<R>, MAX_TURTLE_STACK>,
) -> Result<(), TurtleError> {
    *state = stack.pop().ok_or(TurtleError::UnmatchedPop)?;
    Ok(())
}

/// Appends `p` to `polygon` unless it repeats the last vertex.
fn push_vertex<R: Real>(
    polygon: &mut Vec<Vector3<R>, MAX_POLYGON_VERTICES>,
    p: &Vector3<R>,
) -> Result<(), TurtleError> {
    if polygon.last() == Some(p) {
        return Ok(());
    }
    polygon.push(*p).map_err(|_| TurtleError::TooManyVertices)
}

/// A surface's outline: `(l, h)` points in hundredths of its scale.
pub type Outline = &'static [(i32, i32)];

/// The predefined surfaces `~X` draws (ABOP Sec. 5.1's `~`, L-Py's
/// `~l`): each a polygon outline in the turtle's frame, `(l, h)` in
/// hundredths of the scale along L and H, from the turtle's position
/// (the surface's base) to its tip at `h = 100`.
pub const SURFACES: [(u8, &str, Outline); 2] = [
    (
        b'L',
        "leaf",
        &[
            (0, 0),
            (-25, 30),
            (-30, 55),
            (-20, 80),
            (0, 100),
            (20, 80),
            (30, 55),
            (25, 30),
        ],
    ),
    (
        b'P',
        "petal",
        &[
            (0, 0),
            (-15, 20),
            (-35, 60),
            (-30, 90),
            (0, 100),
            (30, 90),
            (35, 60),
            (15, 20),
        ],
    ),
];

/// An axis of the turtle's own frame, which a turn rotates about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// H: `\` and `/` roll (L towards U).
    Heading,
    /// L: `&` and `^` pitch (U towards H).
    Left,
    /// U: `+` and `-` turn (H towards L).
    Up,
}

/// `(a, b) ← (a·c + b·s, b·c − a·s)`: the rotation of the plane (a, b) that
/// turns a towards b.
fn rotate<R: Real>(a: &mut Vector3<R>, b: &mut Vector3<R>, c: R, s: R) {
    let (x, y) = (*a, *b);
    *a = x * c + y * s;
    *b = y * c - x * s;
}

/// Rotates the frame about `axis` by the angle whose cosine and sine are
/// `c` and `s`, then pulls it back to orthonormal: one Newton step towards
/// unit length for H, L made orthogonal to H and unit, U = H × L. Without
/// the second part the sin/cos rounding (≤ 2 LSB) scales the frame by up to
/// ~3·10⁻⁵ per turn, which compounds along a branch.
fn turn<R: Real>(state: &mut State<R>, axis: Axis, c: R, s: R) {
    match axis {
        Axis::Up => rotate(&mut state.heading, &mut state.left, c, s),
        Axis::Left => rotate(&mut state.up, &mut state.heading, c, s),
        Axis::Heading => rotate(&mut state.left, &mut state.up, c, s),
    }
    orthonormalise(state);
}

/// Pulls a rotated frame back to orthonormal: one Newton step towards
/// unit length for H, L made orthogonal to H and unit, U = H × L.
fn orthonormalise<R: Real>(state: &mut State<R>) {
    let (three, half) = (R::from_int(3), R::from_ratio(1, 2));
    let h = state.heading;
    let h = h * ((three - h.dot(&h)) * half);
    let l = state.left - h * h.dot(&state.left);
    let l = l * ((three - l.dot(&l)) * half);
    state.heading = h;
    state.left = l;
    state.up = h.cross(&l);
}

/// The [`Real`]s a turtle computes with. A turn of the frame is the
/// turtle's hot path: by default it is the generic rotation and
/// orthonormalisation above; [`Fx`] computes the same bits with fewer
/// operations in plain `i64` where no product can saturate.
pub trait Turning: Real {
    /// Rotates the frame of `state` about `axis` by the angle whose cosine
    /// and sine are `c` and `s`, and pulls it back to orthonormal.
    fn turn(state: &mut State<Self>, axis: Axis, c: Self, s: Self) {
        turn(state, axis, c, s);
    }
}

impl Turning for f64 {}

impl Turning for Fx {
    fn turn(state: &mut State<Fx>, axis: Axis, c: Fx, s: Fx) {
        if !exact_turn(state, axis, c, s) {
            turn(state, axis, c, s);
        }
    }
}

/// [`Fx::ONE`] as widened bits.
const ONE: i64 = 1 << 16;

/// `a·b` of two Q16 numbers rounded as [`Fx`]'s `*` rounds it (+½ LSB, then
/// down), without saturating: the same bits whenever they fit an `i32`.
/// Every caller's product is below 2⁴⁸ (see [`exact_turn`]): nothing
/// wraps.
fn mul(a: i64, b: i64) -> i64 {
    a.wrapping_mul(b).wrapping_add(ONE / 2) >> 16
}

/// `v·v` as [`Fx`]'s `v.dot(&v)` rounds it, without saturating, for `|vᵢ|`
/// below 2³²: the squares are taken unsigned, where they do not wrap.
fn square(v: &[i64; 3]) -> i64 {
    v.iter()
        .map(|x| {
            let m = x.unsigned_abs();
            (m.wrapping_mul(m).wrapping_add(ONE as u64 / 2) >> 16) as i64
        })
        .fold(0, i64::wrapping_add)
}

/// `a·b` as [`Fx`]'s `a.dot(&b)` rounds it, without saturating.
fn dot(a: &[i64; 3], b: &[i64; 3]) -> i64 {
    mul(a[0], b[0])
        .wrapping_add(mul(a[1], b[1]))
        .wrapping_add(mul(a[2], b[2]))
}

/// The widened bits of a vector.
fn widen(v: &Vector3<Fx>) -> [i64; 3] {
    [v.x, v.y, v.z].map(|x| i64::from(x.to_bits()))
}

/// Bits proven to fit an `i32` back into a vector.
fn narrow(v: [i64; 3]) -> Vector3<Fx> {
    let [x, y, z] = v.map(|x| Fx::from_bits(x as i32));
    Vector3::new(x, y, z)
}

/// [`rotate`] on widened bits: `(a·c + b·s, b·c − a·s)`, each product
/// rounded as [`mul`] rounds it.
fn rotate_bits(a: &[i64; 3], b: &[i64; 3], c: i64, s: i64) -> ([i64; 3], [i64; 3]) {
    let (ac, bs) = (a.map(|x| mul(x, c)), b.map(|x| mul(x, s)));
    let (bc, as_) = (b.map(|x| mul(x, c)), a.map(|x| mul(x, s)));
    (
        [
            ac[0].wrapping_add(bs[0]),
            ac[1].wrapping_add(bs[1]),
            ac[2].wrapping_add(bs[2]),
        ],
        [
            bc[0].wrapping_sub(as_[0]),
            bc[1].wrapping_sub(as_[1]),
            bc[2].wrapping_sub(as_[2]),
        ],
    )
}

/// `v·k` as [`mul`] rounds it; a factor of exactly 1 leaves every
/// component as it is, so those products are skipped.
fn scale(v: [i64; 3], k: i64) -> [i64; 3] {
    if k == ONE { v } else { v.map(|x| mul(x, k)) }
}

/// [`turn`] for [`Fx`] in plain `i64` arithmetic, with each product
/// rounded as `Fx`'s `*` rounds it: the same bits wherever no saturating
/// operator of the generic code would saturate, which the guards below
/// prove; false, with `state` untouched, where they do not hold.
///
/// Range proof, in units of 1 (2¹⁶ bits):
/// 1. `|c|, |s| ≤ 1` and `|c| + |s| ≤ 3/2` (a sine and cosine of one angle
///    have `|c| + |s| ≤ √2` plus rounding). A product `x·c` (or `y·s`)
///    then fits an `i32` unless `x = −32768`, `c = −1`; there `|s| ≤ 1/2`,
///    so the rotated component is beyond ±16 383 whatever saturated.
///    Rotated components are below 1.5·2³¹ bits, products below 2⁴⁷.
/// 2. `H·H ≤ 4` and `L·L ≤ 4` (the frame of a turtle has unit vectors):
///    every component of H and L is within ±2.01, so step 1 saturated
///    nothing, and from `|H|, |L| ≤ 2.001`: the Newton factor for H is in
///    [−0.51, 1.5], `|H′| ≤ 3.01`, `|H′·L| ≤ 6.1`, `|L − H′(H′·L)| ≤ 20.5`,
///    its square ≤ 421, the factor for L within ±210, `|L′| ≤ 4 310`,
///    each product in `U = H′ × L′` ≤ 13 000 and their difference ≤ 26 000:
///    all below 32 768, so nothing saturates, and every product is below
///    2⁴⁶ bits.
// Inlined into `turn` (the shrub bench: 19.06 M instructions out of line,
// 18.73 M inlined; thumbv7m inlines it anyway).
#[inline]
fn exact_turn(state: &mut State<Fx>, axis: Axis, c: Fx, s: Fx) -> bool {
    let (c, s) = (i64::from(c.to_bits()), i64::from(s.to_bits()));
    if c.abs() > ONE || s.abs() > ONE || c.abs() + s.abs() > 3 * ONE / 2 {
        return false;
    }
    let (h, l, u) = (widen(&state.heading), widen(&state.left), widen(&state.up));
    // `rotate`, keeping only what the orthonormalisation reads (it
    // rebuilds U).
    let (h, l) = match axis {
        Axis::Up => rotate_bits(&h, &l, c, s),
        Axis::Left => (rotate_bits(&u, &h, c, s).1, l),
        Axis::Heading => (h, rotate_bits(&l, &u, c, s).0),
    };
    let hh = square(&h);
    if hh > 4 * ONE || square(&l) > 4 * ONE {
        return false;
    }
    let newton = |squared: i64| mul((3 * ONE).wrapping_sub(squared), ONE / 2);
    let h = scale(h, newton(hh));
    let along = dot(&h, &l);
    // L − H·0 is L: skipped.
    let l = if along == 0 {
        l
    } else {
        let [x, y, z] = h.map(|x| mul(x, along));
        [
            l[0].wrapping_sub(x),
            l[1].wrapping_sub(y),
            l[2].wrapping_sub(z),
        ]
    };
    let l = scale(l, newton(square(&l)));
    let u = [
        mul(h[1], l[2]).wrapping_sub(mul(h[2], l[1])),
        mul(h[2], l[0]).wrapping_sub(mul(h[0], l[2])),
        mul(h[0], l[1]).wrapping_sub(mul(h[1], l[0])),
    ];
    state.heading = narrow(h);
    state.left = narrow(l);
    state.up = narrow(u);
    true
}

impl Turtle<Fx> {
    /// A turtle whose bytes are all zero (no frame, zero parameters), so
    /// that a runner slot holding one is written in place by a memset;
    /// [`Turtle::new`] one before use.
    pub(crate) const fn zeroed() -> Turtle<Fx> {
        let o = Fx::ZERO;
        let zero = Vector3::new(o, o, o);
        Turtle {
            state: State {
                position: zero,
                heading: zero,
                left: zero,
                up: zero,
                width: o,
                colour: 0,
            },
            stack: Vec::new(),
            polygon: Vec::new(),
            polygon_open: false,
            params: Params {
                step: o,
                delta: Angle::ZERO,
                width: o,
                thin: o,
                tropism: zero,
                elasticity: o,
            },
            cos_delta: o,
            sin_delta: o,
        }
    }
}

impl<R: Turning> Turtle<R> {
    /// A turtle at the origin in the initial frame.
    #[must_use]
    pub fn new(params: Params<R>) -> Turtle<R> {
        let mut t = Turtle {
            state: State {
                position: Vector3::zeros(),
                heading: Vector3::y(),
                left: -Vector3::x(),
                up: Vector3::z(),
                width: params.width,
                colour: 0,
            },
            stack: Vec::new(),
            polygon: Vec::new(),
            polygon_open: false,
            params,
            cos_delta: R::cos(params.delta),
            sin_delta: R::sin(params.delta),
        };
        t.reset(Vector3::zeros());
        t
    }

    /// Back to the initial state at `origin`, with empty stacks.
    pub fn reset(&mut self, origin: Vector3<R>) {
        self.state = State {
            position: origin,
            heading: Vector3::y(),
            left: -Vector3::x(),
            up: Vector3::z(),
            width: self.params.width,
            colour: 0,
        };
        self.stack.clear();
        self.polygon.clear();
        self.polygon_open = false;
    }

    /// The current state.
    #[must_use]
    pub fn state(&self) -> &State<R> {
        &self.state
    }

    /// The vertices of the polygon being (or last) recorded.
    #[must_use]
    pub fn polygon(&self) -> &[Vector3<R>] {
        &self.polygon
    }

    /// The current `[` depth.
    #[must_use]
    pub fn depth(&self) -> usize {
        self.stack.len()
    }

    /// Checks the end of a string: no polygon may be open.
    ///
    /// # Errors
    /// [`TurtleError::UnclosedPolygon`].
    pub fn finish(&self) -> Result<(), TurtleError> {
        if self.polygon_open {
            Err(TurtleError::UnclosedPolygon)
        } else {
            Ok(())
        }
    }

    fn angle(&self, m: &Module) -> (R, R) {
        match m.args().first() {
            Some(&deg) => {
                let a = Angle::from_degrees_fx(deg);
                (R::cos(a), R::sin(a))
            }
            None => (self.cos_delta, self.sin_delta),
        }
    }

    fn add_vertex(&mut self) -> Result<(), TurtleError> {
        push_vertex(&mut self.polygon, &self.state.position)
    }

    fn advance(&mut self, m: &Module) -> Result<Vector3<R>, TurtleError> {
        let length = m
            .args()
            .first()
            .map_or(self.params.step, |&l| R::from_fx(l));
        let from = self.state.position;
        let to = from + self.state.heading * length;
        let limit = R::from_int(COORDINATE_LIMIT);
        if to.iter().any(|&x| x.abs() > limit) {
            return Err(TurtleError::OutOfRange);
        }
        self.state.position = to;
        Ok(from)
    }

    /// Tropism (ABOP Sec. 2.2, Eq. 2.3 and Fig. 2.8): rotates the frame by
    /// α = e·‖H × T‖ radians about the axis H × T, which bends H towards
    /// T, then re-orthonormalises it as a turn does. Nothing happens when
    /// e = 0 or when H is within ~2⁻¹² of parallel to T (there α is below
    /// e·2⁻¹² and the axis is lost in rounding).
    fn bend(&mut self) {
        let e = self.params.elasticity;
        if e == R::zero() {
            return;
        }
        let s = &mut self.state;
        let axis = s.heading.cross(&self.params.tropism);
        let norm = R::norm(&axis);
        if norm < R::from_ratio(1, 4096) {
            return;
        }
        let k = Vector3::new(axis.x.div(norm), axis.y.div(norm), axis.z.div(norm));
        let alpha = (e * norm).scale_angle(Angle::from_radians_fx(Fx::ONE));
        let (c, sin) = (R::cos(alpha), R::sin(alpha));
        let one_minus_c = R::one() - c;
        // Rodrigues: v' = v·cos α + (k × v)·sin α + k (k·v)(1 − cos α).
        let rotate = |v: Vector3<R>| v * c + k.cross(&v) * sin + k * (k.dot(&v) * one_minus_c);
        s.heading = rotate(s.heading);
        s.left = rotate(s.left);
        orthonormalise(s);
    }

    /// `~X(s)`: the predefined surface X scaled by s (default 1) as a
    /// polygon in the turtle's frame, left in [`Turtle::polygon`]. Its
    /// module is `~` with the surface's index in [`SURFACES`] as the first
    /// parameter (the parser writes it) and the scale as the second.
    fn surface(&mut self, m: &Module) -> Result<Drawn<R>, TurtleError> {
        if self.polygon_open {
            return Err(TurtleError::NestedPolygon);
        }
        let outline = m
            .args()
            .first()
            .and_then(|&i| usize::try_from(i.floor_int()).ok())
            .and_then(|i| SURFACES.get(i))
            .ok_or(TurtleError::UnknownSurface)?
            .2;
        let scale = m.args().get(1).map_or(R::one(), |&s| R::from_fx(s));
        let s = &self.state;
        let limit = R::from_int(COORDINATE_LIMIT);
        self.polygon.clear();
        for &(l, h) in outline {
            let p = s.position
                + s.left * (R::from_ratio(l, 100) * scale)
                + s.heading * (R::from_ratio(h, 100) * scale);
            if p.iter().any(|&x| x.abs() > limit) {
                return Err(TurtleError::OutOfRange);
            }
            push_vertex(&mut self.polygon, &p)?;
        }
        Ok(Drawn::Polygon {
            colour: self.state.colour,
        })
    }

    /// `$`: rolls about H so that L is horizontal (left unchanged when H is
    /// within ~0.2° of vertical).
    fn level(&mut self) {
        let h = self.state.heading;
        let (lx, lz) = (h.z, -h.x); // V × H with V = +y
        let norm = (lx * lx + lz * lz).sqrt();
        if norm < R::from_ratio(1, 256) {
            return;
        }
        let l = Vector3::new(lx.div(norm), R::zero(), lz.div(norm));
        self.state.left = l;
        self.state.up = Vector3::new(h.y * l.z, h.z * l.x - h.x * l.z, -(h.y * l.x));
    }

    /// Interprets one module.
    ///
    /// # Errors
    /// Stack overflow or underflow, polygon nesting or size, and leaving
    /// the drawable range.
    // Inlined into the L-system's draw loop (the shrub bench: 19.59 M
    // instructions out of line, 19.06 M inlined; thumbv7m inlines it anyway).
    #[inline]
    pub fn apply(&mut self, m: &Module) -> Result<Drawn<R>, TurtleError> {
        let s = &mut self.state;
        match m.symbol {
            b'F' | b'G' => {
                let a = self.advance(m)?;
                if m.symbol == b'F' && self.polygon_open {
                    self.add_vertex()?;
                }
                let (width, colour) = (self.state.width, self.state.colour);
                let b = self.state.position;
                self.bend();
                return Ok(Drawn::Segment {
                    a,
                    b,
                    width,
                    colour,
                });
            }
            b'f' | b'g' => {
                self.advance(m)?;
                if m.symbol == b'f' && self.polygon_open {
                    self.add_vertex()?;
                }
            }
            b'+' | b'-' | b'&' | b'^' | b'\\' | b'/' => {
                let (c, sin) = self.angle(m);
                let sin = if matches!(m.symbol, b'-' | b'^' | b'/') {
                    -sin
                } else {
                    sin
                };
                let axis = match m.symbol {
                    b'+' | b'-' => Axis::Up,
                    b'&' | b'^' => Axis::Left,
                    _ => Axis::Heading,
                };
                R::turn(&mut self.state, axis, c, sin);
            }
            b'|' => {
                s.heading = -s.heading;
                s.left = -s.left;
            }
            b'$' => self.level(),
            b'~' => return self.surface(m),
            b'[' => {
                let copy = *s;
                self.stack
                    .push(copy)
                    .map_err(|_| TurtleError::StackOverflow)?;
            }
            b']' => restore(&mut self.state, &mut self.stack)?,
            b'{' => {
                if self.polygon_open {
                    return Err(TurtleError::NestedPolygon);
                }
                self.polygon_open = true;
                self.polygon.clear();
                self.add_vertex()?;
            }
            b'}' => {
                if !self.polygon_open {
                    return Err(TurtleError::UnmatchedPolygonEnd);
                }
                self.polygon_open = false;
                if self.polygon.len() > 1 && self.polygon.first() == self.polygon.last() {
                    self.polygon.pop();
                }
                return Ok(Drawn::Polygon {
                    colour: self.state.colour,
                });
            }
            b'.' if self.polygon_open => self.add_vertex()?,
            b'!' => {
                s.width = match m.args().first() {
                    Some(&w) if w < Fx::ZERO => return Err(TurtleError::NegativeWidth),
                    Some(&w) => R::from_fx(w),
                    None => s.width * self.params.thin,
                }
            }
            b'\'' => {
                s.colour = match m.args().first() {
                    Some(&c) => {
                        u16::try_from(c.floor_int()).map_err(|_| TurtleError::ColourOutOfRange)?
                    }
                    None => s.colour.saturating_add(1),
                }
            }
            _ => {}
        }
        Ok(Drawn::Nothing)
    }
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use super::*;

    fn params<R: Real>(delta_deg: i32) -> Params<R> {
        Params {
            step: R::one(),
            delta: Angle::from_degrees(delta_deg),
            width: R::one(),
            thin: R::from_ratio(1, 2),
            tropism: Vector3::zeros(),
            elasticity: R::zero(),
        }
    }

    fn run<R: Turning>(text: &str, delta_deg: i32) -> (Turtle<R>, std::vec::Vec<Drawn<R>>) {
        let mut t = Turtle::new(params::<R>(delta_deg));
        let drawn = text
            .bytes()
            .map(|b| t.apply(&Module::bare(b)).unwrap())
            .filter(|d| *d != Drawn::Nothing)
            .collect();
        (t, drawn)
    }

    fn v(x: i32, y: i32, z: i32) -> Vector3<Fx> {
        Vector3::new(Fx::from_int(x), Fx::from_int(y), Fx::from_int(z))
    }

    fn ends(drawn: &[Drawn<Fx>]) -> std::vec::Vec<Vector3<Fx>> {
        drawn
            .iter()
            .filter_map(|d| match d {
                Drawn::Segment { b, .. } => Some(*b),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn turns_are_pinned() {
        // + turns left (towards −x seen from +z), & pitches down (towards −z),
        // \ rolls L towards U so a following + turns towards +z.
        assert_eq!(ends(&run("F+F", 90).1), [v(0, 1, 0), v(-1, 1, 0)]);
        assert_eq!(ends(&run("F-F", 90).1), [v(0, 1, 0), v(1, 1, 0)]);
        assert_eq!(ends(&run("F&F", 90).1), [v(0, 1, 0), v(0, 1, -1)]);
        assert_eq!(ends(&run("F^F", 90).1), [v(0, 1, 0), v(0, 1, 1)]);
        assert_eq!(ends(&run("F\\+F", 90).1), [v(0, 1, 0), v(0, 1, 1)]);
        assert_eq!(ends(&run("F/+F", 90).1), [v(0, 1, 0), v(0, 1, -1)]);
        assert_eq!(ends(&run("F|F", 90).1), [v(0, 1, 0), v(0, 0, 0)]);
        let (t, _) = run::<Fx>("+&\\", 90);
        let s = t.state();
        // H × L = U is kept by every rotation.
        assert_eq!(s.heading.cross(&s.left), s.up);
    }

    #[test]
    fn dollar_levels_the_left_axis() {
        for text in ["&+\\\\$", "^^-/$", "+&&&\\$"] {
            let (t, _) = run::<f64>(text, 30);
            let s = t.state();
            assert!(s.left.y.abs() < 1e-12, "{text}: L = {:?}", s.left);
            assert!(s.up.y > 0.0, "{text}: U = {:?}", s.up);
            assert!(
                (s.heading.cross(&s.left) - s.up)
                    .iter()
                    .all(|x| x.abs() < 1e-12)
            );
            let (tf, _) = run::<Fx>(text, 30);
            let sf = tf.state();
            assert_eq!(sf.left.y, Fx::ZERO, "{text}");
            assert!((sf.up.y.to_f64() - s.up.y).abs() < 1e-4);
        }
        // Vertical heading: $ leaves the frame alone.
        assert_eq!(run::<Fx>("$", 30).0.state().left, -Vector3::x());
    }

    #[test]
    fn width_colour_and_polygons() {
        let (_, drawn) = run::<Fx>("F!F'F", 90);
        let widths: std::vec::Vec<_> = drawn
            .iter()
            .filter_map(|d| match d {
                Drawn::Segment { width, colour, .. } => Some((*width, *colour)),
                _ => None,
            })
            .collect();
        assert_eq!(
            widths,
            [(Fx::ONE, 0), (Fx::HALF, 0), (Fx::HALF, 1)],
            "! halves, ' counts"
        );
        // A unit square from f moves: 4 vertices, the closing one dropped.
        let (t, drawn) = run::<Fx>("{f+f+f+f}", 90);
        assert_eq!(drawn, [Drawn::Polygon { colour: 0 }]);
        assert_eq!(
            t.polygon(),
            [v(0, 0, 0), v(0, 1, 0), v(-1, 1, 0), v(-1, 0, 0)]
        );
    }

    #[test]
    fn stack_errors() {
        let mut t = Turtle::new(params::<Fx>(90));
        assert_eq!(t.apply(&Module::bare(b']')), Err(TurtleError::UnmatchedPop));
        for _ in 0..MAX_TURTLE_STACK {
            t.apply(&Module::bare(b'[')).unwrap();
        }
        assert_eq!(
            t.apply(&Module::bare(b'[')),
            Err(TurtleError::StackOverflow)
        );
        let mut t = Turtle::new(params::<Fx>(90));
        t.apply(&Module::bare(b'{')).unwrap();
        assert_eq!(t.finish(), Err(TurtleError::UnclosedPolygon));
        assert_eq!(
            t.apply(&Module::bare(b'{')),
            Err(TurtleError::NestedPolygon)
        );
        let mut t = Turtle::new(params::<Fx>(90));
        assert_eq!(
            t.apply(&Module::bare(b'}')),
            Err(TurtleError::UnmatchedPolygonEnd)
        );
        let mut far = Module::bare(b'F');
        far.arity = 1;
        far.params[0] = Fx::from_int(20_000);
        assert_eq!(t.apply(&far), Err(TurtleError::OutOfRange));
    }

    #[test]
    fn exact_turn_is_the_generic_turn_bit_for_bit() {
        // Frames near unit, larger, and anywhere in the I16F16 range (where
        // the guards send the turn to the generic code), turned about every
        // axis by sine/cosine pairs and by raw extremes.
        let mut seed = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = move || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 32) as i32
        };
        let extremes = [i32::MIN, i32::MAX, -65_536, 65_536, 0, 98_304];
        let (mut exact, mut total) = (0, 0);
        for k in 0..30_000 {
            let mut component = || match k % 4 {
                0 => Fx::from_bits(next() >> 15),
                1 => Fx::from_bits(next() >> 13),
                2 => Fx::from_bits(next()),
                _ => Fx::from_bits(extremes[next().unsigned_abs() as usize % 6]),
            };
            let mut vector = || Vector3::new(component(), component(), component());
            let state = State {
                position: Vector3::zeros(),
                heading: vector(),
                left: vector(),
                up: vector(),
                width: Fx::ONE,
                colour: 0,
            };
            let (c, s) = if k % 3 == 0 {
                let raw = |r: i32| Fx::from_bits(extremes[r.unsigned_abs() as usize % 6]);
                (raw(next()), raw(next()))
            } else {
                let a = Angle(next() as u32);
                (<Fx as Real>::cos(a), <Fx as Real>::sin(a))
            };
            for axis in [Axis::Heading, Axis::Left, Axis::Up] {
                let (mut fast, mut generic) = (state, state);
                <Fx as Turning>::turn(&mut fast, axis, c, s);
                turn(&mut generic, axis, c, s);
                assert_eq!(fast, generic, "{axis:?} by ({c}, {s}) of {state:?}");
                exact += usize::from(exact_turn(&mut state.clone(), axis, c, s));
                total += 1;
            }
        }
        // Both paths are exercised.
        assert!(
            exact > total / 10 && exact < total / 2,
            "{exact} of {total}"
        );
    }
}
