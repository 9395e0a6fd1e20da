//! What the L-system targets assert of a grammar the model refuses.

use morphogen::Error;
use morphogen::lsys::LsysError;

/// Asserts that `e`, the refusal of `text`, is a parse error at a line
/// and column within the text.
pub fn assert_located(text: &str, e: &Error) {
    let lines = text.split('\n').count();
    assert!(
        matches!(e, Error::Lsys(LsysError::Parse(p))
            if p.line >= 1 && p.column >= 1 && p.line as usize <= lines),
        "refused without a line and column in the text: {e}"
    );
}
