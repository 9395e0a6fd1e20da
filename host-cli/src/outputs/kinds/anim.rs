//! `anim`: the frames' pictures as one animated PNG (`animation.png`),
//! drawn and handed over in order by the driver.

use super::{Format, Kind, Product};

/// The kind.
pub(super) const KIND: Kind = Kind {
    name: "anim",
    about: "animation.png",
    by_default: true,
    format: &Anim,
};

/// The animation's file name.
pub const ANIMATION: &str = "animation.png";

struct Anim;

impl Format for Anim {
    fn takes(&self, product: Product) -> bool {
        product == Product::Animation
    }
}
