//! A user's body: an OBJ mesh and a cylinder file (format in
//! `docs/body.md`), named by a `[body]` scenario's `mesh` and `cylinders`
//! (or `morphogen run --mesh --cylinders`). Every error names the file and
//! line; every number is checked so that nothing saturates later.

use std::collections::HashMap;

use morphogen::body::{Anchor, BodyModel, Cylinder, Drive, Feature, GrowthTable, Label};
use morphogen::fx::{Angle, Fx};

/// An error: `NAME:LINE: what is wrong`.
type Result<T> = std::result::Result<T, String>;

/// Capacity of a user body (cylinders); the built-in ones use 24.
pub const USER_CYLINDERS: usize = 64;

/// The largest coordinate of a mesh vertex or a cylinder point: a body
/// grown a few times its size must stay inside the fixed-point range
/// (±32 767), so nothing saturates.
pub const MAX_COORDINATE: f64 = 2048.0;

/// The most vertices of a user mesh (a run streams every vertex of every
/// frame: 200 000 vertices are 5 MB a frame).
pub const MAX_MESH_VERTICES: usize = 200_000;

/// The oldest model age and table age, months.
pub const MAX_AGE_MONTHS: f64 = 1200.0;

/// A triangle mesh read from an OBJ file.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct ObjMesh {
    /// `v` lines.
    pub vertices: Vec<[Fx; 3]>,
    /// `f` lines, fan-triangulated, 0-based.
    pub triangles: Vec<[u32; 3]>,
    /// The line of each vertex, for errors about it.
    pub vertex_lines: Vec<usize>,
}

/// A token shown in an error, at most 24 characters of it.
fn shown(token: &str) -> String {
    match token.char_indices().nth(24) {
        Some((at, _)) => format!("{}…", &token[..at]),
        None => token.to_string(),
    }
}

/// A number within ±`limit` as I16F16, refusing what does not fit.
fn number_within(token: &str, limit: f64) -> Result<Fx> {
    let v: f64 = token
        .parse()
        .map_err(|_| format!("'{}' is not a number", shown(token)))?;
    if !v.is_finite() || v.abs() > limit {
        return Err(format!(
            "{} is out of range (allowed: -{limit} to {limit})",
            shown(token)
        ));
    }
    Ok(Fx::from_bits((v * 65_536.0).round() as i32))
}

/// A coordinate (±[`MAX_COORDINATE`]).
fn number(token: &str) -> Result<Fx> {
    number_within(token, MAX_COORDINATE)
}

fn numbers<const N: usize>(tokens: &[&str]) -> Result<[Fx; N]> {
    if tokens.len() < N {
        return Err(format!("expected {N} numbers, found {}", tokens.len()));
    }
    let mut out = [Fx::ZERO; N];
    for (o, t) in out.iter_mut().zip(tokens) {
        *o = number(t)?;
    }
    Ok(out)
}

/// Parses OBJ text: `v` and `f` (with `v/vt/vn` forms and negative
/// indices); other statements are ignored.
///
/// # Errors
/// `name:line: message` for a malformed line or an index out of range.
pub fn parse_obj(name: &str, text: &str) -> Result<ObjMesh> {
    let mut mesh = ObjMesh::default();
    for (n, line) in text.lines().enumerate() {
        let at = || format!("{name}:{}", n + 1);
        let line = line.split('#').next().unwrap_or("");
        let tokens: Vec<&str> = line.split_whitespace().collect();
        match tokens.first().copied() {
            Some("v") => {
                if mesh.vertices.len() == MAX_MESH_VERTICES {
                    return Err(format!(
                        "{}: more than {MAX_MESH_VERTICES} vertices (body_files::MAX_MESH_VERTICES); simplify the mesh",
                        at()
                    ));
                }
                let p = numbers::<3>(&tokens[1..]).map_err(|e| format!("{}: {e}", at()))?;
                mesh.vertices.push(p);
                mesh.vertex_lines.push(n + 1);
            }
            Some("f") => {
                let count = mesh.vertices.len() as i64;
                let mut ids = Vec::with_capacity(tokens.len() - 1);
                for t in &tokens[1..] {
                    let first = t.split('/').next().unwrap_or("");
                    let i: i64 = first
                        .parse()
                        .map_err(|_| format!("{}: face index '{t}' is not an integer", at()))?;
                    let id = if i < 0 { count + i } else { i - 1 };
                    if !(0..count).contains(&id) {
                        return Err(format!(
                            "{}: face index {i} refers to no vertex ({count} so far)",
                            at()
                        ));
                    }
                    ids.push(id as u32);
                }
                if ids.len() < 3 {
                    return Err(format!("{}: a face needs at least 3 vertices", at()));
                }
                for k in 1..ids.len() - 1 {
                    mesh.triangles.push([ids[0], ids[k], ids[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if mesh.triangles.is_empty() {
        return Err(format!("{name}: no faces (`f` lines) found"));
    }
    Ok(mesh)
}

/// A cylinder file: the cylinders, the model's age and the line of each
/// cylinder (for errors found later).
#[derive(Debug, Clone)]
pub struct CylinderFile {
    /// Root first.
    pub cylinders: Vec<Cylinder>,
    /// `model-age`, months.
    pub model_age: Fx,
    /// Where each cylinder was declared.
    pub lines: HashMap<String, usize>,
}

/// Parses a cylinder file against `table` (whose column names features
/// refer to). See `docs/body.md`.
///
/// # Errors
/// `name:line: message` for anything malformed or inconsistent.
pub fn parse_cylinders(name: &str, text: &str, table: &GrowthTable<'_>) -> Result<CylinderFile> {
    let mut cylinders: Vec<Cylinder> = Vec::new();
    let mut features: Vec<Vec<Feature>> = Vec::new();
    let mut lines = HashMap::new();
    let mut model_age = None;
    for (n, line) in text.lines().enumerate() {
        let at = format!("{name}:{}", n + 1);
        let line = line.split('#').next().unwrap_or("");
        let t: Vec<&str> = line.split_whitespace().collect();
        let Some(&keyword) = t.first() else { continue };
        match keyword {
            "model-age" => {
                if t.len() != 2 {
                    return Err(format!("{at}: expected `model-age MONTHS`"));
                }
                if model_age.is_some() {
                    return Err(format!("{at}: a second `model-age`"));
                }
                let age = number_within(t[1], MAX_AGE_MONTHS).map_err(|e| format!("{at}: {e}"))?;
                if age < Fx::ZERO {
                    return Err(format!(
                        "{at}: model-age {} is negative (allowed: 0 to {MAX_AGE_MONTHS})",
                        t[1]
                    ));
                }
                model_age = Some(age);
            }
            "cylinder" => {
                // cylinder NAME parent P|- base X Y Z tip X Y Z radius R [roll DEG]
                let shape = t.len() == 14 || t.len() == 16;
                if !shape
                    || t[2] != "parent"
                    || t[4] != "base"
                    || t[8] != "tip"
                    || t[12] != "radius"
                    || (t.len() == 16 && t[14] != "roll")
                {
                    return Err(format!(
                        "{at}: expected `cylinder NAME parent PARENT|- base X Y Z tip X Y Z radius R [roll DEGREES]`"
                    ));
                }
                let label = Label::try_new(t[1]).ok_or_else(|| {
                    format!(
                        "{at}: cylinder name '{}' is longer than 16 bytes",
                        shown(t[1])
                    )
                })?;
                if cylinders.len() == USER_CYLINDERS {
                    return Err(format!(
                        "{at}: more than {USER_CYLINDERS} cylinders (body_files::USER_CYLINDERS)"
                    ));
                }
                if lines.contains_key(t[1]) {
                    return Err(format!("{at}: cylinder '{}' is declared twice", t[1]));
                }
                let parent = match t[3] {
                    "-" => None,
                    p => Some(
                        cylinders
                            .iter()
                            .position(|c| c.name.as_str() == p)
                            .ok_or_else(|| {
                                format!("{at}: parent '{p}' must be declared before '{}'", t[1])
                            })?,
                    ),
                };
                if parent.is_none() != cylinders.is_empty() {
                    return Err(format!(
                        "{at}: the first cylinder is the root (parent -), and only it"
                    ));
                }
                // Fewer than USER_CYLINDERS (64) cylinders: an index fits a u8.
                let parent = parent.and_then(|p| u8::try_from(p).ok());
                let roll = if t.len() == 16 {
                    Angle::from_degrees_fx(number(t[15]).map_err(|e| format!("{at}: {e}"))?)
                } else {
                    Angle::ZERO
                };
                let placeholder = Feature {
                    from: [Fx::ZERO; 3],
                    to: [Fx::ZERO; 3],
                    anchor: Anchor::Canonical,
                    drive: Drive::Follows(0),
                };
                cylinders.push(Cylinder {
                    name: label,
                    parent,
                    base: numbers::<3>(&t[5..8]).map_err(|e| format!("{at}: {e}"))?,
                    tip: numbers::<3>(&t[9..12]).map_err(|e| format!("{at}: {e}"))?,
                    radius: number(t[13]).map_err(|e| format!("{at}: {e}"))?,
                    roll,
                    features: [placeholder; 2],
                });
                features.push(Vec::new());
                lines.insert(t[1].to_string(), n + 1);
            }
            "feature" => {
                // feature CYLINDER measured|follows COLUMN model|canonical X1 Y1 Z1 X2 Y2 Z2
                if t.len() != 11 {
                    return Err(format!(
                        "{at}: expected `feature CYLINDER measured|follows COLUMN model|canonical X1 Y1 Z1 X2 Y2 Z2`"
                    ));
                }
                let c = cylinders
                    .iter()
                    .position(|c| c.name.as_str() == t[1])
                    .ok_or_else(|| format!("{at}: no cylinder '{}' declared before", t[1]))?;
                let index = |name: &str| {
                    table.column_index(name).ok_or_else(|| {
                        let known: Vec<&str> =
                            table.columns.iter().map(|c| c.name.as_str()).collect();
                        format!(
                            "{at}: the growth table has no column '{name}' (it has {})",
                            known.join(", ")
                        )
                    })
                };
                let drive = match t[2] {
                    "measured" => Drive::Measured(index(t[3])?),
                    "follows" => Drive::Follows(index(t[3])?),
                    "below" => {
                        let Some((column, above)) = t[3].split_once('/') else {
                            return Err(format!(
                                "{at}: `below` takes COLUMN/ABOVE (the height and the column the part above the feature follows)"
                            ));
                        };
                        Drive::Below {
                            column: index(column)?,
                            above: index(above)?,
                        }
                    }
                    other => {
                        return Err(format!(
                            "{at}: '{other}' must be `measured`, `follows` or `below`"
                        ));
                    }
                };
                let anchor = match t[4] {
                    "model" => Anchor::Model,
                    "canonical" => Anchor::Canonical,
                    other => return Err(format!("{at}: '{other}' must be `model` or `canonical`")),
                };
                let p = numbers::<6>(&t[5..11]).map_err(|e| format!("{at}: {e}"))?;
                if features[c].len() == 2 {
                    return Err(format!(
                        "{at}: cylinder '{}' already has two features",
                        t[1]
                    ));
                }
                features[c].push(Feature {
                    from: [p[0], p[1], p[2]],
                    to: [p[3], p[4], p[5]],
                    anchor,
                    drive,
                });
            }
            other => {
                return Err(format!(
                    "{at}: unknown statement '{other}' (model-age, cylinder, feature)"
                ));
            }
        }
    }
    if cylinders.is_empty() {
        return Err(format!("{name}: no cylinder declared"));
    }
    for (c, f) in cylinders.iter_mut().zip(&features) {
        if f.len() != 2 {
            return Err(format!(
                "{name}:{}: cylinder '{}' needs exactly two features, has {}",
                lines.get(c.name.as_str()).copied().unwrap_or(0),
                c.name,
                f.len()
            ));
        }
        c.features = [f[0], f[1]];
    }
    let model_age = model_age.ok_or_else(|| format!("{name}: missing `model-age MONTHS`"))?;
    Ok(CylinderFile {
        cylinders,
        model_age,
        lines,
    })
}

/// Writes `model`'s cylinders in the cylinder-file format (column names
/// from `table`), e.g. to start a user body from a built-in one.
#[must_use]
pub fn format_cylinders(model: &BodyModel<'_>, table: &GrowthTable<'_>) -> String {
    use std::fmt::Write as _;
    // Exact: an I16F16 value is an f64 whose shortest form round-trips.
    let n = |v: Fx| f64::from(v.to_bits()) / 65_536.0;
    let p = |v: [Fx; 3]| format!("{} {} {}", n(v[0]), n(v[1]), n(v[2]));
    let mut s = format!("model-age {}\n", n(model.model_age));
    for c in model.cylinders {
        let parent = c.parent.map_or("-".to_string(), |i| {
            model.cylinders[usize::from(i)].name.to_string()
        });
        let _ = write!(
            s,
            "cylinder {} parent {parent} base {} tip {} radius {}",
            c.name,
            p(c.base),
            p(c.tip),
            n(c.radius)
        );
        if c.roll != Angle::ZERO {
            let _ = write!(s, " roll {}", n(c.roll.to_degrees_fx()));
        }
        s.push('\n');
        for f in &c.features {
            let name = |k: u8| {
                table
                    .columns
                    .get(usize::from(k))
                    .map_or("?", |c| c.name.as_str())
            };
            let (kind, column) = match f.drive {
                Drive::Measured(k) => ("measured", name(k).to_string()),
                Drive::Follows(k) => ("follows", name(k).to_string()),
                Drive::Below { column, above } => {
                    ("below", format!("{}/{}", name(column), name(above)))
                }
            };
            let anchor = match f.anchor {
                Anchor::Model => "model",
                Anchor::Canonical => "canonical",
            };
            let _ = writeln!(
                s,
                "feature {} {kind} {column} {anchor} {} {}",
                c.name,
                p(f.from),
                p(f.to)
            );
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use morphogen::body::table::QUARTER_HORSE;

    use super::*;

    #[test]
    fn obj_faces_are_fan_triangulated_and_located_errors() {
        let m = parse_obj(
            "m.obj",
            "# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1 -1//1\n",
        )
        .unwrap();
        assert_eq!(m.vertices.len(), 4);
        assert_eq!(m.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        let e = parse_obj("m.obj", "v 0 0 0\nv 1 0 0\nf 1 2 3\n").unwrap_err();
        assert!(e.to_string().starts_with("m.obj:3:"), "{e}");
        let e = parse_obj("m.obj", "v 0 0 abc\n").unwrap_err();
        assert!(format!("{e:#}").contains("m.obj:1"), "{e:#}");
        let e = parse_obj("m.obj", "v 0 0 40000\n").unwrap_err();
        assert!(format!("{e:#}").contains("range"), "{e:#}");
    }

    const CYLINDERS: &str = "\
model-age 60
cylinder body parent - base 0 10 0 tip 20 10 0 radius 5
feature body follows elbow-to-ground model 0 10 0 20 10 0
feature body measured cannon-diameter canonical 0.5 -0.2 0 0.5 0.2 0
cylinder leg parent body base 5 6 0 tip 5 0 0 radius 2
feature leg measured elbow-to-ground model 5 6 0 5 0 0
feature leg follows cannon-diameter canonical 0.5 0 -1 0.5 0 1
";

    #[test]
    fn the_built_in_horse_round_trips_through_the_file_format() {
        let horse = &morphogen::body::quadruped::HORSE;
        let text = format_cylinders(horse, &QUARTER_HORSE);
        let f = parse_cylinders("horse.cylinders", &text, &QUARTER_HORSE).unwrap();
        assert_eq!(f.cylinders, horse.cylinders);
        assert_eq!(f.model_age, horse.model_age);
    }

    #[test]
    fn cylinder_files_parse_and_errors_name_the_line() {
        let f = parse_cylinders("c.txt", CYLINDERS, &QUARTER_HORSE).unwrap();
        assert_eq!(f.cylinders.len(), 2);
        assert_eq!(f.cylinders[1].parent, Some(0));
        assert_eq!(f.cylinders[1].features[0].drive, Drive::Measured(0));
        assert_eq!(f.lines["leg"], 5);
        let bad = CYLINDERS.replace("elbow-to-ground model 5", "elbow-to-knee model 5");
        let e = parse_cylinders("c.txt", &bad, &QUARTER_HORSE).unwrap_err();
        assert!(
            e.starts_with("c.txt:6:") && e.contains("elbow-to-knee"),
            "{e}"
        );
        let bad = CYLINDERS.replace("parent body", "parent hip");
        let e = parse_cylinders("c.txt", &bad, &QUARTER_HORSE).unwrap_err();
        assert!(e.starts_with("c.txt:5:"), "{e}");
        let bad: String = CYLINDERS
            .lines()
            .take(6)
            .map(|l| format!("{l}\n"))
            .collect();
        let e = parse_cylinders("c.txt", &bad, &QUARTER_HORSE).unwrap_err();
        assert!(
            e.contains("c.txt:5: cylinder 'leg' needs exactly two features"),
            "{e}"
        );
    }

    #[test]
    fn values_that_would_saturate_are_errors_naming_the_line() {
        let e = parse_obj("m.obj", "v 0 0 0\nv 32000 0 0\n").unwrap_err();
        assert!(
            format!("{e:#}").contains("m.obj:2") && format!("{e:#}").contains("2048"),
            "{e:#}"
        );
        for (age, message) in [
            ("-5", "c.txt:1: model-age -5 is negative"),
            ("32766", "c.txt:1: 32766 is out of range"),
        ] {
            let bad = CYLINDERS.replace("model-age 60", &format!("model-age {age}"));
            let e = parse_cylinders("c.txt", &bad, &QUARTER_HORSE).unwrap_err();
            assert!(format!("{e:#}").contains(message), "{e:#}");
        }
        let twice = format!("{CYLINDERS}model-age 12\n");
        let e = parse_cylinders("c.txt", &twice, &QUARTER_HORSE).unwrap_err();
        assert!(
            format!("{e:#}").contains("c.txt:8: a second `model-age`"),
            "{e:#}"
        );
        let mut many = CYLINDERS.to_string();
        for i in 0..USER_CYLINDERS {
            many.push_str(&format!(
                "cylinder c{i} parent body base 0 0 0 tip 1 0 0 radius 1\n"
            ));
        }
        let e = parse_cylinders("c.txt", &many, &QUARTER_HORSE).unwrap_err();
        assert!(
            format!("{e:#}").contains(&format!("more than {USER_CYLINDERS} cylinders")),
            "{e:#}"
        );
    }

    #[test]
    fn a_mesh_beyond_the_vertex_limit_is_refused_at_its_line() {
        let text = "v 0 0 0\n".repeat(MAX_MESH_VERTICES + 1);
        let e = parse_obj("big.obj", &text).unwrap_err().to_string();
        assert!(
            e.starts_with(&format!(
                "big.obj:{}: more than {MAX_MESH_VERTICES} vertices",
                MAX_MESH_VERTICES + 1
            )),
            "{e}"
        );
    }
}
