//! The built-in L-system presets' grammars. Their text is the example
//! files in `grammars/`, compiled in, so what a user reads is what runs.

/// ABOP Fig. 1.25, the three-dimensional shrub (n = 7, δ = 22.5°).
pub const SHRUB: &str = include_str!("../../../grammars/abop-shrub.lsys");
/// ABOP Fig. 1.24a, a 2D bracketed plant (n = 5, δ = 25.7°).
pub const PLANT_2D: &str = include_str!("../../../grammars/abop-2d-plant.lsys");
/// ABOP Fig. 1.27, three stochastic plants from three seeds.
pub const STOCHASTIC: &str = include_str!("../../../grammars/abop-stochastic.lsys");
/// ABOP Fig. 2.6a, the parametric monopodial tree (n = 10).
pub const MONOPODIAL: &str = include_str!("../../../grammars/abop-monopodial.lsys");

/// Every preset grammar with its preset name.
pub const ALL: [(&str, &str); 4] = [
    ("abop-shrub", SHRUB),
    ("abop-2d-plant", PLANT_2D),
    ("abop-stochastic", STOCHASTIC),
    ("abop-monopodial", MONOPODIAL),
];
