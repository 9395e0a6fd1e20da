//! Sizing a cylinder from its two features (growth paper, Sec. 6).
//!
//! With the feature points fixed in the cylinder's canonical space, a
//! feature of measured length Lᵢ satisfies
//! `Lᵢ² = L²·Δxᵢ² + R²·(Δyᵢ² + Δzᵢ²)`: two features give a 2×2 linear
//! system in L² and R², singular when both segments have the same axial vs
//! radial proportions.
//!
//! The system is solved in a dimensionless form that suits I16F16: divide
//! feature i by its model length mᵢ and write the unknowns as squared
//! growth ratios α = (L/L₀)², β = (R/R₀)². Then `λᵢ² = α·Uᵢ + β·Vᵢ` with
//! λᵢ = Lᵢ/mᵢ and Uᵢ + Vᵢ = 1 the axial and radial shares of the feature
//! (all of order 1, so no square of a length ever overflows), and
//! `det = U₁V₂ − U₂V₁` is the sine-like measure of how different the two
//! features' proportions are.

use super::cylinder::{Cylinder, Drive, Rest, norm};
use super::{BodyError, GrowthTable};
use crate::fx::{Fx, Real};

/// The smallest |det| accepted: features whose axial shares differ by less
/// than 1/64 are treated as singular (their solution would amplify the
/// fixed-point rounding by more than 64).
pub const MIN_DETERMINANT: Fx = Fx::from_ratio(1, 64);

/// A cylinder's growth G = diag(L, R, R) relative to its model size: the
/// ratios L/L₀ and R/R₀.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Growth<R: Real> {
    /// L / L₀, the scale along the axis.
    pub length: R,
    /// R / R₀, the scale across it.
    pub radius: R,
}

impl<R: Real> Growth<R> {
    /// The model's own size.
    #[must_use]
    pub fn model() -> Growth<R> {
        Growth {
            length: R::one(),
            radius: R::one(),
        }
    }
}

/// A feature's shape in the cylinder: its model length and its axial and
/// radial shares U, V (U + V = 1).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Shape<R: Real> {
    model_length: R,
    axial: R,
    radial: R,
}

fn shapes<R: Real>(cylinder: &Cylinder, rest: &Rest<R>) -> Result<[Shape<R>; 2], BodyError> {
    let shape = |i: usize| {
        let e = rest.feature_vector(&cylinder.features[i]);
        let m = norm(&e);
        if m <= R::zero() {
            return Err(BodyError::DegenerateFeature {
                cylinder: cylinder.name,
            });
        }
        let u = e.map(|x| x.div(m));
        Ok(Shape {
            model_length: m,
            axial: u.x * u.x,
            radial: u.y * u.y + u.z * u.z,
        })
    };
    Ok([shape(0)?, shape(1)?])
}

fn determinant<R: Real>(s: &[Shape<R>; 2]) -> R {
    s[0].axial * s[1].radial - s[1].axial * s[0].radial
}

/// Checks a cylinder's features once: both have a length, their columns
/// exist, and the system is not singular.
///
/// # Errors
/// [`BodyError::DegenerateFeature`], [`BodyError::UnknownColumn`] or
/// [`BodyError::SingularFeatures`].
pub fn check<R: Real>(
    cylinder: &Cylinder,
    rest: &Rest<R>,
    table: &GrowthTable<'_>,
) -> Result<(), BodyError> {
    for f in &cylinder.features {
        for column in f.drive.columns() {
            if usize::from(column) >= table.columns.len() {
                return Err(BodyError::UnknownColumn {
                    cylinder: cylinder.name,
                    column,
                });
            }
        }
    }
    let s = shapes(cylinder, rest)?;
    if determinant(&s).abs() < R::from_fx(MIN_DETERMINANT) {
        return Err(BodyError::SingularFeatures {
            cylinder: cylinder.name,
        });
    }
    Ok(())
}

/// The length a feature must have at `age`, and its model length.
fn target<R: Real>(
    cylinder: &Cylinder,
    drive: Drive,
    model_length: R,
    table: &GrowthTable<'_>,
    age: R,
    model_age: R,
) -> Result<R, BodyError> {
    let column = drive.column();
    let missing = BodyError::UnknownColumn {
        cylinder: cylinder.name,
        column,
    };
    let now = table.value(column, age).ok_or(missing)?;
    Ok(match drive {
        Drive::Measured(_) => now,
        Drive::Follows(_) => {
            let then = table.value(column, model_age).ok_or(missing)?;
            // model_length·(now/then): the ratio first, it is of order 1.
            model_length * now.div(then)
        }
        Drive::Below { above, .. } => {
            let then = table.value(column, model_age).ok_or(missing)?;
            let missing = BodyError::UnknownColumn {
                cylinder: cylinder.name,
                column: above,
            };
            let (above_now, above_then) = (
                table.value(above, age).ok_or(missing)?,
                table.value(above, model_age).ok_or(missing)?,
            );
            // The part above, (then − model)·(above_now/above_then): the
            // ratio first, of order 1.
            now - (then - model_length) * above_now.div(above_then)
        }
    })
}

/// The length feature `i` of `cylinder` must have at `age` (months), in
/// the table's unit.
///
/// # Errors
/// [`BodyError::UnknownColumn`] when the table has no value of a column
/// the feature is driven by.
pub fn feature_target<R: Real>(
    cylinder: &Cylinder,
    rest: &Rest<R>,
    i: usize,
    table: &GrowthTable<'_>,
    age: R,
    model_age: R,
) -> Result<R, BodyError> {
    let s = shapes(cylinder, rest)?;
    let k = i.min(1);
    target(
        cylinder,
        cylinder.features[k].drive,
        s[k].model_length,
        table,
        age,
        model_age,
    )
}

/// Solves the 2×2 system of `cylinder` at `age` (months): its growth
/// relative to the model, which was built at `model_age`.
///
/// # Errors
/// [`BodyError::SingularFeatures`] naming the cylinder, or
/// [`BodyError::NegativeSize`] when the lengths contradict the geometry
/// (plus the errors of [`check`]).
pub fn solve<R: Real>(
    cylinder: &Cylinder,
    rest: &Rest<R>,
    table: &GrowthTable<'_>,
    age: R,
    model_age: R,
) -> Result<Growth<R>, BodyError> {
    let s = shapes(cylinder, rest)?;
    let det = determinant(&s);
    if det.abs() < R::from_fx(MIN_DETERMINANT) {
        return Err(BodyError::SingularFeatures {
            cylinder: cylinder.name,
        });
    }
    let mut lambda2 = [R::zero(); 2];
    for (i, l2) in lambda2.iter_mut().enumerate() {
        let t = target(
            cylinder,
            cylinder.features[i].drive,
            s[i].model_length,
            table,
            age,
            model_age,
        )?;
        let lambda = t.div(s[i].model_length);
        *l2 = lambda * lambda;
    }
    // Cramer's rule on [U₁ V₁; U₂ V₂]·[α β]ᵀ = [λ₁² λ₂²]ᵀ; every term is
    // of order 1 (growth ratios are within 1/8..8 for real animals).
    let alpha = (lambda2[0] * s[1].radial - lambda2[1] * s[0].radial).div(det);
    let beta = (s[0].axial * lambda2[1] - s[1].axial * lambda2[0]).div(det);
    if alpha <= R::zero() || beta <= R::zero() {
        return Err(BodyError::NegativeSize {
            cylinder: cylinder.name,
            age: None,
        });
    }
    Ok(Growth {
        length: alpha.sqrt(),
        radius: beta.sqrt(),
    })
}

#[cfg(test)]
#[allow(clippy::float_arithmetic)]
mod tests {
    use nalgebra::Vector3;

    use super::*;
    use crate::body::cylinder::{Anchor, Feature};
    use crate::body::{Label, table};
    use crate::fx::Angle;

    fn fx3(v: [f64; 3]) -> [Fx; 3] {
        v.map(|x| Fx::from_bits((x * 65_536.0).round() as i32))
    }

    fn cylinder(f1: ([f64; 3], [f64; 3]), f2: ([f64; 3], [f64; 3])) -> Cylinder {
        let feature = |(a, b): ([f64; 3], [f64; 3]), column| Feature {
            from: fx3(a),
            to: fx3(b),
            anchor: Anchor::Canonical,
            drive: Drive::Measured(column),
        };
        Cylinder {
            name: Label::new("shin"),
            parent: None,
            base: fx3([0.0, 0.0, 0.0]),
            tip: fx3([0.0, -10.0, 0.0]),
            radius: Fx::from_int(2),
            roll: Angle::ZERO,
            features: [
                feature(f1, table::horse::ELBOW_TO_GROUND),
                feature(f2, table::horse::CANNON_DIAMETER),
            ],
        }
    }

    #[test]
    fn oblique_features_give_the_paper_solution() {
        // Feature 1 oblique, feature 2 mostly radial: a genuine 2×2 system.
        let c = cylinder(
            ([0.0, 0.0, 0.0], [3.0, 0.5, 0.0]),
            ([0.5, -0.6, 0.1], [0.6, 0.6, 0.1]),
        );
        let table = &table::QUARTER_HORSE;
        let rest = Rest::<f64>::of(&c).unwrap();
        for age in [0.0, 12.0, 30.0, 60.0] {
            let g = solve(&c, &rest, table, age, 60.0).unwrap();
            let (l, r) = (g.length * rest.length, g.radius * rest.radius);
            for (i, f) in c.features.iter().enumerate() {
                let d = Vector3::new(
                    f.to[0].to_f64() - f.from[0].to_f64(),
                    f.to[1].to_f64() - f.from[1].to_f64(),
                    f.to[2].to_f64() - f.from[2].to_f64(),
                );
                // The paper's equation, literally.
                let l_i = (l * l * d.x * d.x + r * r * (d.y * d.y + d.z * d.z)).sqrt();
                let want = table.value(f.drive.column(), age).unwrap();
                assert!(
                    (l_i - want).abs() < 1e-9,
                    "feature {i} at {age}: {l_i} vs {want}"
                );
            }
            let gf = solve(
                &c,
                &Rest::<Fx>::of(&c).unwrap(),
                table,
                Fx::from_int(age as i32),
                Fx::from_int(60),
            )
            .unwrap();
            assert!((gf.length.to_f64() - g.length).abs() < 2e-4);
            assert!((gf.radius.to_f64() - g.radius).abs() < 2e-4);
        }
    }

    #[test]
    fn same_proportions_are_singular_and_name_the_cylinder() {
        // Both features along the axis.
        let c = cylinder(
            ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0]),
            ([0.2, 0.3, 0.0], [0.9, 0.3, 0.0]),
        );
        let rest = Rest::<Fx>::of(&c).unwrap();
        let e = solve(&c, &rest, &table::QUARTER_HORSE, Fx::ONE, Fx::ONE);
        assert_eq!(
            e,
            Err(BodyError::SingularFeatures {
                cylinder: Label::new("shin")
            })
        );
        assert_eq!(check(&c, &rest, &table::QUARTER_HORSE), e.map(|_| ()));
        // Parallel oblique segments of different lengths: same proportions.
        let c = cylinder(
            ([0.0, 0.0, 0.0], [1.0, 1.0, 0.0]),
            ([0.0, 0.0, 0.0], [0.5, 0.0, 0.5]),
        );
        let rest = Rest::<f64>::of(&c).unwrap();
        assert!(matches!(
            solve(&c, &rest, &table::QUARTER_HORSE, 1.0, 1.0),
            Err(BodyError::SingularFeatures { .. })
        ));
    }

    #[test]
    fn contradictory_lengths_are_refused() {
        // Both features mostly axial, feature 1 asking for 35.8 in and
        // feature 2 (more radial) for only 2.51 in: no positive R² fits.
        let c = cylinder(
            ([0.0, 0.0, 0.0], [1.0, 0.05, 0.0]),
            ([0.0, 0.0, 0.0], [0.9, 1.0, 0.0]),
        );
        let rest = Rest::<f64>::of(&c).unwrap();
        assert!(matches!(
            solve(&c, &rest, &table::QUARTER_HORSE, 60.0, 60.0),
            Err(BodyError::NegativeSize { .. })
        ));
    }
}
