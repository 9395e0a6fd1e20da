//! `morphogen run BODY --mesh FILE --cylinders FILE`: a body scenario's
//! growth table, ages and gait on the user's mesh and cylinders — the same
//! as a `[body]` scenario naming them (`docs/body.md`), whose readers are
//! `morphogen_scenario::body_files`.

use std::path::Path;

use anyhow::{Result, anyhow, bail};
use morphogen_scenario::Scenario;

/// `scenario` (a `[body]` one) growing the OBJ `mesh` bound to the
/// `cylinders` file instead of its built-in body. The paths are relative to
/// the current folder.
///
/// # Errors
/// A scenario that is not a body, a path that is not UTF-8, or a mistake
/// in either file, named by the file and line.
pub fn with_body_files(scenario: &Scenario, mesh: &Path, cylinders: &Path) -> Result<Scenario> {
    let mut doc: toml_edit::DocumentMut = scenario.self_contained().parse()?;
    let Some(body) = doc.get_mut("body").and_then(|b| b.as_table_like_mut()) else {
        bail!(
            "--mesh/--cylinders need a body scenario (horse-growth, cow-growth, horse-trot, or a [body] file), not '{}'",
            scenario.name()
        );
    };
    let path = |p: &Path| {
        p.to_str()
            .map(str::to_string)
            .ok_or_else(|| anyhow!("{}: the path is not UTF-8", p.display()))
    };
    body.remove("model");
    body.insert("mesh", toml_edit::value(path(mesh)?));
    body.insert("cylinders", toml_edit::value(path(cylinders)?));
    Scenario::from_text_in(scenario.origin(), &doc.to_string(), Path::new(".")).map_err(|e| {
        // A mistake in the user's files is named by their own file and line.
        if e.key == "body.mesh" || e.key == "body.cylinders" {
            anyhow!("{}", e.message)
        } else {
            anyhow!("{e}")
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const CYLINDERS: &str = "\
model-age 60
cylinder body parent - base 0 10 0 tip 20 10 0 radius 5
feature body follows elbow-to-ground model 0 10 0 20 10 0
feature body measured cannon-diameter canonical 0.5 -0.2 0 0.5 0.2 0
";

    #[test]
    fn a_vertex_in_too_many_cylinders_is_named_with_its_line() {
        let tmp = tempfile::tempdir().unwrap();
        let mut cylinders = CYLINDERS.to_string();
        for i in 0..9 {
            cylinders.push_str(&format!(
                "cylinder c{i} parent body base 0 10 0 tip 20 10 0 radius 5\n\
                 feature c{i} follows elbow-to-ground model 0 10 0 20 10 0\n\
                 feature c{i} measured cannon-diameter canonical 0.5 -0.2 0 0.5 0.2 0\n"
            ));
        }
        let (mesh, cyl) = (tmp.path().join("m.obj"), tmp.path().join("c.txt"));
        std::fs::write(
            &mesh,
            "# one triangle\nv 30 30 30\nv 10 10 0\nv 30 31 30\nf 1 2 3\n",
        )
        .unwrap();
        std::fs::write(&cyl, cylinders).unwrap();
        let horse = morphogen_scenario::builtin("horse-growth").unwrap();
        let e = with_body_files(&horse, &mesh, &cyl)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with(&format!(
                "{}:3: vertex 2 lies in more than 8 cylinders",
                mesh.display()
            )),
            "{e}"
        );
    }

    #[test]
    fn only_a_body_scenario_takes_a_mesh() {
        let horn = morphogen_scenario::builtin("ram-horn").unwrap();
        let e = with_body_files(&horn, Path::new("m.obj"), Path::new("c.txt"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("need a body scenario"), "{e}");
    }
}
