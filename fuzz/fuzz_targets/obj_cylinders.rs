//! Fuzzes the user-body readers (`docs/body.md`): an OBJ mesh and a
//! cylinder file read against the quarter-horse growth table. The input is
//! the OBJ text, a NUL byte, then the cylinder text (without a NUL, the
//! whole input is given to both). A refused file's error starts with its
//! name; when both are read, the binding of mesh to cylinders (what `run
//! --mesh --cylinders` does next) either works or gives an error. No input
//! may panic.
//!
//! `RUSTC_BOOTSTRAP=1 cargo fuzz run obj_cylinders` from the repository
//! root (or `bash scripts/fuzz.sh`; docs/robustness.md).
#![no_main]

use libfuzzer_sys::fuzz_target;
use morphogen::body::table::QUARTER_HORSE;
use morphogen::body::{BodyModel, Mesh};
use morphogen_scenario::body_files::{USER_CYLINDERS, parse_cylinders, parse_obj};

/// Meshes bound to cylinders at most this many vertices (bounds the time).
const BIND_VERTICES: usize = 4096;

fuzz_target!(|data: &[u8]| {
    let (obj, cylinders) = match data.iter().position(|&b| b == 0) {
        Some(at) => (&data[..at], &data[at + 1..]),
        None => (data, data),
    };
    let (Ok(obj), Ok(cylinders)) = (core::str::from_utf8(obj), core::str::from_utf8(cylinders))
    else {
        return;
    };
    let mesh = parse_obj("m.obj", obj);
    if let Err(e) = &mesh {
        let shown = format!("{e:#}");
        assert!(shown.starts_with("m.obj"), "{shown}");
        assert!(shown.len() < 4096, "error of {} bytes", shown.len());
    }
    let file = parse_cylinders("c.txt", cylinders, &QUARTER_HORSE);
    if let Err(e) = &file {
        let shown = format!("{e:#}");
        assert!(shown.starts_with("c.txt"), "{shown}");
        assert!(shown.len() < 4096, "error of {} bytes", shown.len());
    }
    let (Ok(mesh), Ok(file)) = (mesh, file) else {
        return;
    };
    assert!(file.cylinders.len() <= USER_CYLINDERS);
    if mesh.vertices.len() > BIND_VERTICES {
        return;
    }
    let model = BodyModel {
        cylinders: &file.cylinders,
        mesh: Mesh::Indexed {
            vertices: &mesh.vertices,
            triangles: &mesh.triangles,
        },
        model_age: file.model_age,
    };
    let _ = morphogen::body::binding_summary::<USER_CYLINDERS>(&model, &QUARTER_HORSE);
});
