//! What can be wrong with a body model, its growth table or its mesh.

use super::Label;
use crate::fx::Fx;

/// A body that cannot be grown; each variant names the cylinder, column or
/// mesh element at fault.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum BodyError {
    /// The model has no cylinder.
    NoCylinders,
    /// A cylinder's parent does not come before it in the list (the list
    /// must be in hierarchy order, root first).
    ParentOrder {
        /// The child.
        cylinder: Label,
    },
    /// A cylinder has no length or no radius.
    DegenerateCylinder {
        /// The cylinder.
        cylinder: Label,
    },
    /// One of a cylinder's two features has zero length in the model.
    DegenerateFeature {
        /// The cylinder.
        cylinder: Label,
    },
    /// The two features of a cylinder have the same proportions along the
    /// axis (X) and across it (YZ), so L² and R² are not determined
    /// (the 2×2 system of the growth paper, Sec. 6, is singular).
    SingularFeatures {
        /// The cylinder.
        cylinder: Label,
    },
    /// The measured lengths contradict the features' geometry: the 2×2
    /// system gives L² ≤ 0 or R² ≤ 0.
    NegativeSize {
        /// The cylinder.
        cylinder: Label,
        /// The age (months) it was sized for, once known: a run names its
        /// frame's ([`BodyError::at_age`]).
        age: Option<Fx>,
    },
    /// A feature names a column the growth table does not have.
    UnknownColumn {
        /// The cylinder.
        cylinder: Label,
        /// The column index.
        column: u8,
    },
    /// The growth table has no age, or its ages are not strictly increasing.
    TableAges,
    /// A table column's length differs from the number of ages, or it holds
    /// a value that is not positive.
    TableColumn {
        /// The column's name.
        column: Label,
    },
    /// A triangle refers to a vertex the mesh does not have.
    TriangleVertex {
        /// The triangle's index.
        triangle: u32,
    },
    /// A procedural tube has fewer than 2 stations or 3 sides.
    DegenerateTube {
        /// The tube's index.
        tube: u16,
    },
    /// The run has no frame, or a gait has no phase.
    ZeroCount,
}

impl core::fmt::Display for BodyError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BodyError::NoCylinders => f.write_str("the body has no cylinder"),
            BodyError::ParentOrder { cylinder } => write!(
                f,
                "cylinder '{cylinder}': its parent must be listed before it"
            ),
            BodyError::DegenerateCylinder { cylinder } => {
                write!(f, "cylinder '{cylinder}' has no length or no radius")
            }
            BodyError::DegenerateFeature { cylinder } => {
                write!(f, "cylinder '{cylinder}': a feature has zero length")
            }
            BodyError::SingularFeatures { cylinder } => write!(
                f,
                "cylinder '{cylinder}': its two features have the same axial vs radial proportions, \
                 so length and radius cannot both be solved (singular 2x2 system)"
            ),
            BodyError::NegativeSize { cylinder, age } => {
                write!(f, "cylinder '{cylinder}'")?;
                if let Some(age) = age {
                    write!(f, " at age {age:.2} months")?;
                }
                f.write_str(": the measured lengths give a negative L² or R²")
            }
            BodyError::UnknownColumn { cylinder, column } => write!(
                f,
                "cylinder '{cylinder}': the growth table has no column {column}"
            ),
            BodyError::TableAges => {
                f.write_str("growth table: ages must be present and strictly increasing")
            }
            BodyError::TableColumn { column } => write!(
                f,
                "growth table column '{column}': one positive value per age is needed"
            ),
            BodyError::TriangleVertex { triangle } => {
                write!(f, "triangle {triangle} refers to a missing vertex")
            }
            BodyError::DegenerateTube { tube } => {
                write!(f, "tube {tube} needs at least 2 stations and 3 sides")
            }
            BodyError::ZeroCount => f.write_str("the run needs at least one frame and gait phase"),
        }
    }
}

impl BodyError {
    /// This error of a body sized for `age` (months): a
    /// [`BodyError::NegativeSize`] names it; the others are unchanged.
    #[must_use]
    pub fn at_age(self, age: Fx) -> BodyError {
        match self {
            BodyError::NegativeSize {
                cylinder,
                age: None,
            } => BodyError::NegativeSize {
                cylinder,
                age: Some(age),
            },
            e => e,
        }
    }
}

impl core::error::Error for BodyError {}
