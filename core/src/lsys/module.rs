//! A module of an L-system string: a symbol and its actual parameters
//! (ABOP Sec. 1.10). The leaf type that the derivation writes and the
//! turtle reads.

use crate::fx::Fx;

/// Parameters of one module.
pub const MAX_PARAMS: usize = 4;

/// A module: a symbol and its actual parameters (`F(2.5)`, `+`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Module {
    /// The symbol, a printable ASCII byte.
    pub symbol: u8,
    /// How many of `params` are used.
    pub arity: u8,
    /// The parameter values; those past `arity` are zero.
    pub params: [Fx; MAX_PARAMS],
}

impl Module {
    /// A module without parameters.
    #[must_use]
    pub const fn bare(symbol: u8) -> Module {
        Module {
            symbol,
            arity: 0,
            params: [Fx::ZERO; MAX_PARAMS],
        }
    }

    /// The parameters in use.
    #[must_use]
    pub fn args(&self) -> &[Fx] {
        self.params.get(..self.arity as usize).unwrap_or(&[])
    }
}
