//! What ABOP and L-Py mean by the module symbols the core's grammar parser
//! refuses (`morphogen::lsys::UNSUPPORTED_SYMBOLS`), told where a grammar
//! comes in (scenario files, `--set`, `run --grammar`, the web page), so
//! that the explanations cost a device's flash nothing.

use morphogen::lsys::ParseErrorKind;

/// The meaning `symbol` has in ABOP or L-Py, and what to use instead.
fn meaning(symbol: u8) -> Option<&'static str> {
    Some(match symbol {
        b'@' => {
            "L-Py/cpfg multi-letter turtle commands (@O sphere, @o circle, @M move to, @Tp tropism, ...)"
        }
        b'?' => "L-Py/cpfg query modules (?P position, ?H heading, ...) that read the turtle back",
        b'_' => "L-Py: increase the width (use `!(w)` to set it)",
        b';' => "L-Py: next colour index (use `'` or `'(c)`)",
        _ => return None,
    })
}

/// `kind` as a message: an unsupported symbol with its meaning elsewhere,
/// any other kind as the core words it.
pub(crate) fn explained(kind: &ParseErrorKind) -> String {
    match kind {
        ParseErrorKind::UnsupportedSymbol { symbol } => match meaning(*symbol) {
            Some(meaning) => format!(
                "the symbol `{}` is not supported (its meaning elsewhere: {meaning})",
                char::from(*symbol)
            ),
            None => kind.to_string(),
        },
        _ => kind.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use morphogen::lsys::UNSUPPORTED_SYMBOLS;

    /// Every symbol the core refuses is explained here, and a grammar
    /// using one is refused at the door with its meaning.
    #[test]
    fn every_refused_symbol_has_its_meaning() {
        for symbol in UNSUPPORTED_SYMBOLS {
            assert!(meaning(symbol).is_some(), "`{}`", char::from(symbol));
        }
        let e =
            crate::check::grammar("n = 1\naxiom: F @O(1)\n", "mine.lsys", |_, _| {}).unwrap_err();
        assert_eq!(
            e,
            "mine.lsys:2:10: the symbol `@` is not supported (its meaning elsewhere: L-Py/cpfg \
             multi-letter turtle commands (@O sphere, @o circle, @M move to, @Tp tropism, ...))"
        );
    }
}
