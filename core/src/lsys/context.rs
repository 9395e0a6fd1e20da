//! Context search in constant time (ABOP p. 32). Looking left from a
//! module, ignored symbols and whole branches `[…]` are skipped and `[`
//! climbs to the parent; looking right, ignored symbols and lateral
//! branches are skipped and `]` ends the search. Done by scanning, as
//! L-Py and cpfg do, a step costs up to the square of the string (every
//! module of `X[X[X[…]]]` skips the branch after it); here one pass each
//! way links every position to where the searches land, and matching a
//! context follows links.

use super::{Grammar, Module};

/// No position.
const NONE: u32 = u32::MAX;

/// Where the context searches go from one position of a string (caller
/// memory for [`super::Buffered`], one per module).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Neighbours {
    /// The nearest context candidate before the position.
    before: u32,
    /// The nearest candidate at or after it (at a `]` it holds a link of
    /// the pass that computes it: read through [`Context::from`]).
    from: u32,
}

/// The `from` link of position `j` (none at a `]`, whose `from` is the
/// pass's own).
fn from_in(string: &[Module], links: &[Neighbours], j: usize) -> u32 {
    match (string.get(j), links.get(j)) {
        (Some(m), Some(link)) if m.symbol != b']' => link.from,
        _ => NONE,
    }
}

fn position(link: u32) -> Option<usize> {
    (link != NONE).then_some(link as usize)
}

/// A string with its [`Neighbours`]: what the contexts of a production are
/// matched against.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Context<'s> {
    string: &'s [Module],
    links: &'s [Neighbours],
}

/// Links the positions of `string` in `links` (which holds at least
/// `string.len()`; positions past it have no neighbours).
pub(crate) fn link<
    const PRODUCTIONS: usize,
    const SUCCESSORS: usize,
    const CONTEXTS: usize,
    const CODE: usize,
    const LITERALS: usize,
>(
    g: &Grammar<PRODUCTIONS, SUCCESSORS, CONTEXTS, CODE, LITERALS>,
    string: &[Module],
    links: &mut [Neighbours],
) {
    let n = string.len().min(links.len());
    // Left to right: `open` is the innermost unclosed `[`, each `[`
    // keeping the one around it in its `from` (overwritten below).
    let (mut before, mut open) = (NONE, NONE);
    for j in 0..n {
        let (Some(m), Some(link)) = (string.get(j), links.get_mut(j)) else {
            break;
        };
        link.before = before;
        match m.symbol {
            b'[' => {
                link.from = open;
                open = j as u32;
            }
            b']' => match links.get(open as usize) {
                Some(&outer) if open != NONE => {
                    before = outer.before;
                    open = outer.from;
                }
                _ => before = NONE,
            },
            symbol if g.is_ignored(symbol) => {}
            _ => before = j as u32,
        }
    }
    // Right to left: `close` is the innermost unopened `]`, each `]`
    // keeping the one around it in its `from`.
    let mut close = NONE;
    for j in (0..n).rev() {
        let Some(m) = string.get(j) else { continue };
        let from = match m.symbol {
            b']' => core::mem::replace(&mut close, j as u32),
            b'[' => match links.get(close as usize) {
                Some(&outer) if close != NONE => {
                    let after = close as usize + 1;
                    close = outer.from;
                    from_in(string, links, after)
                }
                _ => NONE,
            },
            symbol if g.is_ignored(symbol) => from_in(string, links, j + 1),
            _ => j as u32,
        };
        if let Some(link) = links.get_mut(j) {
            link.from = from;
        }
    }
}

impl<'s> Context<'s> {
    /// `string` with the `links` [`link`] gave it.
    pub(crate) fn new(string: &'s [Module], links: &'s [Neighbours]) -> Context<'s> {
        Context { string, links }
    }

    /// The module at `j`.
    pub(crate) fn get(&self, j: usize) -> Option<&'s Module> {
        self.string.get(j)
    }

    /// The nearest context candidate before `j`.
    pub(crate) fn before(&self, j: usize) -> Option<usize> {
        position(self.links.get(j)?.before)
    }

    /// The nearest context candidate at or after `j`: `None` at the end of
    /// a branch or of the string.
    pub(crate) fn from(&self, j: usize) -> Option<usize> {
        position(from_in(self.string, self.links, j))
    }
}

#[cfg(test)]
mod tests {
    use std::vec;
    use std::vec::Vec;

    use super::*;
    use crate::rng::KeyedRng;

    /// ABOP p. 32 by scanning: the candidate before `j`.
    fn scan_before(g: &Grammar, s: &[Module], mut j: usize) -> Option<usize> {
        loop {
            j = j.checked_sub(1)?;
            match s.get(j)?.symbol {
                b']' => {
                    let mut depth = 1u32;
                    while depth > 0 {
                        j = j.checked_sub(1)?;
                        match s.get(j)?.symbol {
                            b']' => depth += 1,
                            b'[' => depth -= 1,
                            _ => {}
                        }
                    }
                }
                b'[' => {}
                sym if g.is_ignored(sym) => {}
                _ => return Some(j),
            }
        }
    }

    /// ABOP p. 32 by scanning: the candidate at or after `j`.
    fn scan_from(g: &Grammar, s: &[Module], mut j: usize) -> Option<usize> {
        loop {
            match s.get(j)?.symbol {
                b'[' => {
                    let mut depth = 1u32;
                    while depth > 0 {
                        j += 1;
                        match s.get(j)?.symbol {
                            b'[' => depth += 1,
                            b']' => depth -= 1,
                            _ => {}
                        }
                    }
                    j += 1;
                }
                b']' => return None,
                sym if g.is_ignored(sym) => j += 1,
                _ => return Some(j),
            }
        }
    }

    #[test]
    fn links_land_where_scanning_does() {
        // Random strings of brackets (unbalanced too), ignored and other
        // symbols: every position's links against the scans.
        let mut g = Grammar::new();
        g.parse("n = 1\nignore: + -\naxiom: A").unwrap();
        let alphabet = *b"[[]]+-AB";
        let mut rng = KeyedRng::new(7, 0);
        for round in 0..2000 {
            let len = (rng.next_u32() % 40) as usize;
            let s: Vec<Module> = (0..len)
                .map(|_| Module::bare(alphabet[(rng.next_u32() % 8) as usize]))
                .collect();
            let mut links = vec![Neighbours::default(); len];
            link(&g, &s, &mut links);
            let c = Context::new(&s, &links);
            let text: std::string::String = s.iter().map(|m| m.symbol as char).collect();
            for j in 0..=len {
                if j < len {
                    assert_eq!(
                        c.before(j),
                        scan_before(&g, &s, j),
                        "{round} `{text}` before {j}"
                    );
                }
                assert_eq!(c.from(j), scan_from(&g, &s, j), "{round} `{text}` from {j}");
            }
        }
    }

    #[test]
    fn nested_branches_link_past_each_other() {
        let mut g = Grammar::new();
        g.parse("n = 1\naxiom: A").unwrap();
        let s: Vec<Module> = b"A[B[C]D]E".iter().map(|&b| Module::bare(b)).collect();
        let mut links = vec![Neighbours::default(); s.len()];
        link(&g, &s, &mut links);
        let c = Context::new(&s, &links);
        // Right of A: its lateral branch is skipped to E.
        assert_eq!(c.from(1), Some(8));
        // Left of E: the branch is skipped to A; left of D: C's branch to B.
        assert_eq!(c.before(8), Some(0));
        assert_eq!(c.before(6), Some(2));
        // Left of C: climbs out to B; right of D: the branch ends.
        assert_eq!(c.before(4), Some(2));
        assert_eq!(c.from(7), None);
    }
}
