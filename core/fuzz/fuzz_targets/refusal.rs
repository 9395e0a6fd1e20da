//! What the L-system targets assert of a grammar the model refuses.

use morphogen::Error;
use morphogen::lsys::LsysError;

/// Asserts that `e`, the refusal of `text` by a default `LSystem`, is a
/// parse error at a line and column within the text, or the one refusal
/// of a grammar that parsed: interpretation rules nested deeper than the
/// type's `INTERPRETATION` (8) draws.
pub fn assert_located(text: &str, e: &Error) {
    let too_deep = LsysError::Capacity {
        limit: "INTERPRETATION",
        capacity: 8,
    };
    if *e == Error::Lsys(too_deep) {
        return;
    }
    let lines = text.split('\n').count();
    assert!(
        matches!(e, Error::Lsys(LsysError::Parse(p))
            if p.line >= 1 && p.column >= 1 && p.line as usize <= lines),
        "refused without a line and column in the text: {e}"
    );
}
