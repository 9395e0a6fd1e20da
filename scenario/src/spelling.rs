//! A grammar's misspelt settings, refused at the door: a `name = value`
//! that no expression reads and whose name is close to a setting's would
//! otherwise be a constant that does nothing (`detla = 30` leaves δ at 90°,
//! `elasticty = 0.2` leaves tropism off). The core's parser reports every
//! definition and whether it is read ([`Definition`]); the guess at what
//! was meant, a host's nicety, is made here, off the devices' flash.

use morphogen::lsys::{Definition, SETTINGS};

/// Names other L-system programs give a setting (cpfg's `angle`
/// increment, a count of derivation `steps`), with the setting they mean.
const ALIASES: [(&str, &str); 3] = [("angle", "delta"), ("steps", "n"), ("iterations", "n")];

/// The setting `name` is most likely a misspelling of, if it is close to
/// one (and is not one): its name in another case, a name other programs
/// give it, or within one edit (two for settings of six letters or more;
/// a transposition is one edit).
#[must_use]
pub fn misspelt_setting(name: &str) -> Option<&'static str> {
    if SETTINGS.contains(&name) {
        return None;
    }
    if let Some(&(_, setting)) = ALIASES
        .iter()
        .find(|(alias, _)| alias.eq_ignore_ascii_case(name))
    {
        return Some(setting);
    }
    let name = name.to_ascii_lowercase();
    SETTINGS
        .iter()
        .map(|&s| (strsim::osa_distance(&name, s), s))
        .filter(|&(d, s)| match s.len() {
            1 => d == 0,
            2..=5 => d <= 1,
            _ => d <= 2,
        })
        .min_by_key(|&(d, _)| d)
        .map(|(_, s)| s)
}

/// What is wrong with `name`, a misspelling of `setting`.
fn message(name: &str, setting: &str) -> String {
    format!(
        "unknown setting `{name}`: did you mean `{setting}`? (a name close to a setting's \
         that no rule reads is taken for a misspelling; settings: {})",
        SETTINGS.join(", ")
    )
}

/// If `d` is a misspelt setting (no expression reads it and its name is
/// close to a setting's): its line, column and message.
#[must_use]
pub fn misspelt(d: &Definition<'_>) -> Option<(u32, u32, String)> {
    let setting = misspelt_setting(d.name).filter(|_| !d.read)?;
    Some((d.line, d.column, message(d.name, setting)))
}

/// For a grammar refused on `line`: the column and message if that line
/// defines a misspelt setting (`tropsim = 0, -1, 0` fails as a list,
/// which only the tropism is), the more useful thing to say.
#[must_use]
pub fn misspelt_on_line(text: &str, line: u32) -> Option<(u32, String)> {
    let written = text
        .lines()
        .nth(usize::try_from(line).ok()?.checked_sub(1)?)?;
    let (name, _) = written.split_once('=')?;
    let column = written.len() - written.trim_start().len() + 1;
    let name = name.trim();
    if !name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_') {
        return None;
    }
    let setting = misspelt_setting(name)?;
    Some((u32::try_from(column).ok()?, message(name, setting)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `text` parsed, then checked for a misspelt setting: its line,
    /// column and message.
    fn checked(text: &str) -> Option<(u32, u32, String)> {
        let mut defined = Vec::new();
        let mut grammar = Box::new(morphogen::lsys::Grammar::new());
        let parsed = grammar.parse_with(text, |d| {
            defined.push((d.name.to_owned(), Definition { name: "", ..d }));
        });
        let defined: Vec<Definition<'_>> = defined
            .iter()
            .map(|(name, d)| Definition { name, ..*d })
            .collect();
        defined.iter().find_map(misspelt).or_else(|| {
            let e = parsed.err()?;
            misspelt_on_line(text, e.line).map(|(c, m)| (e.line, c, m))
        })
    }

    #[test]
    fn a_misspelt_setting_no_rule_reads_is_located_and_named() {
        // Each would leave its setting at the default: δ at 90°, no tropism.
        for (text, line, column, name, setting) in [
            (
                "n = 2\ndetla = 30\naxiom: F\nF -> F+F",
                2,
                1,
                "detla",
                "delta",
            ),
            (
                "n = 2\naxiom: F\n  elasticty = 0.2\nF -> F+F",
                3,
                3,
                "elasticty",
                "elasticity",
            ),
            ("n = 2\nDelta = 30\naxiom: F", 2, 1, "Delta", "delta"),
            ("N = 2\naxiom: F", 1, 1, "N", "n"),
            ("n = 2\nangle = 30\naxiom: F", 2, 1, "angle", "delta"),
            ("n = 2\nsteps = 4\naxiom: F", 2, 1, "steps", "n"),
            ("n = 2\nwidht = 3\naxiom: F", 2, 1, "widht", "width"),
            ("n = 2\nplnats = 3\naxiom: F", 2, 1, "plnats", "plants"),
            (
                "n = 2\ntropsim = 0, -1, 0\naxiom: F",
                2,
                1,
                "tropsim",
                "tropism",
            ),
        ] {
            let (l, c, m) = checked(text).unwrap_or_else(|| panic!("{text}: accepted"));
            assert_eq!((l, c), (line, column), "{text}");
            assert!(
                m.starts_with(&format!(
                    "unknown setting `{name}`: did you mean `{setting}`?"
                )),
                "{text}: {m}"
            );
        }
    }

    #[test]
    fn a_constant_that_is_read_or_far_from_a_setting_is_a_constant() {
        for text in [
            "n = 2\ndetla = 30\naxiom: F\nF -> F+(detla)F",
            "n = 2\nwidht = 3\naxiom: F(widht)",
            "n = 2\nstem = 3\nr = stem * 2\naxiom: F(r)",
            "n = 2\nbranch_angle = 30\naxiom: F",
            "n = 2\nr1 = 0.9\naxiom: F",
        ] {
            assert_eq!(checked(text), None, "{text}");
        }
        assert_eq!(misspelt_setting("delta"), None);
        assert_eq!(misspelt_setting("deltaa"), Some("delta"));
        assert_eq!(misspelt_setting("x"), None);
        assert_eq!(misspelt_setting("elastic"), None);
        assert_eq!(misspelt_setting("averyveryverylongname"), None);
    }
}
