//! The kinds of output file `morphogen run` writes, as `--only` selects
//! them. A model states its products ([`Product`]: a frame's mesh, a
//! chart of the run, a table…); each kind, in a module of its own, says
//! which products it takes and writes them in its format (`Format`);
//! `KINDS` lists them. A new kind of file is a new module here and its
//! line in `KINDS`: the models and the driver hand it their products
//! unchanged.

use std::fmt;
use std::path::{Path, PathBuf};

use anyhow::{Result, bail};

use super::chart::Chart;
use super::mesh::{Mesh, ObjStyle};
use super::plot::Drawing;

mod anim;
mod csv;
mod glb;
mod jsonl;
mod obj;
mod plot;
mod png;
mod svg;

pub use self::anim::ANIMATION;

/// What a model makes of its run, for the kinds of file that take it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Product {
    /// A mesh per frame, each in a file of its own (`frame_007.obj`).
    FrameMesh,
    /// The frames' meshes together: their materials, a scene of them.
    FrameMeshes,
    /// A picture per frame (`day_05.png`), and a montage of some.
    FramePicture,
    /// The frames' pictures in sequence.
    Animation,
    /// A picture of the whole run (`horn.png`, `mosaic.png`).
    Picture,
    /// A mesh of the whole run (`surface.obj`, a plant's last frame).
    Mesh,
    /// A chart of the run.
    Chart,
    /// A table (of the run, or of a frame).
    Table,
    /// Pen strokes of the last frame.
    Drawing,
    /// Every record as text.
    Records,
}

/// How a kind writes the products it takes; every product a kind does not
/// take has a default of no file.
pub(crate) trait Format: Sync {
    /// Whether it takes `product`.
    fn takes(&self, product: Product) -> bool;

    /// Writes `chart`, `size` pixels, as `dir/stem.*`.
    ///
    /// # Errors
    /// When the chart cannot be drawn or the file written.
    fn chart(
        &self,
        _chart: &Chart,
        _dir: &Path,
        _stem: &str,
        _size: (u32, u32),
    ) -> Result<Option<PathBuf>> {
        Ok(None)
    }

    /// Writes a table as `dir/stem.*` by `write`, which writes it at the
    /// path it is given.
    ///
    /// # Errors
    /// When `write` fails.
    fn table(
        &self,
        _dir: &Path,
        _stem: &str,
        _write: &mut dyn FnMut(&Path) -> Result<()>,
    ) -> Result<Option<PathBuf>> {
        Ok(None)
    }

    /// Writes a picture as `dir/stem.*` by `save`, which saves it as a
    /// PNG at the path it is given.
    ///
    /// # Errors
    /// When `save` fails.
    fn picture(
        &self,
        _dir: &Path,
        _stem: &str,
        _save: &mut dyn FnMut(&Path) -> Result<()>,
    ) -> Result<Option<PathBuf>> {
        Ok(None)
    }

    /// Writes `mesh` as `dir/stem.*`, in `style` where the format has one.
    ///
    /// # Errors
    /// When a file cannot be written.
    fn mesh(
        &self,
        _mesh: &Mesh,
        _dir: &Path,
        _stem: &str,
        _style: ObjStyle,
    ) -> Result<Vec<PathBuf>> {
        Ok(Vec::new())
    }

    /// Starts a mesh of the whole run that comes a piece at a time (a
    /// plant's last frame, larger than memory allows to hold).
    ///
    /// # Errors
    /// When a file cannot be started.
    fn mesh_stream(
        &self,
        _dir: &Path,
        _stream: &StreamedMesh<'_>,
    ) -> Result<Option<Box<dyn MeshStream>>> {
        Ok(None)
    }

    /// Writes a frame's mesh as a file of its own, the `name` (a numbered
    /// file's name without its extension) given: on a drawing worker.
    ///
    /// # Errors
    /// When the file cannot be written.
    fn frame_mesh(
        &self,
        _mesh: &Mesh,
        _dir: &Path,
        _name: &str,
        _files: &MeshFiles,
    ) -> Result<Option<PathBuf>> {
        Ok(None)
    }

    /// Starts what takes the frames' meshes together, in order.
    fn frame_meshes(&self, _dir: &Path, _files: &MeshFiles) -> Option<Box<dyn MeshSeries>> {
        None
    }

    /// Writes `drawing` into `dir`.
    ///
    /// # Errors
    /// When the file cannot be written.
    fn drawing(&self, _drawing: &Drawing, _dir: &Path) -> Result<Option<PathBuf>> {
        Ok(None)
    }
}

/// The meshes' files: the material library beside the frames' OBJ files
/// and the glTF scene.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct MeshFiles {
    /// The material library's file name (`horn.mtl`).
    pub library: &'static str,
    /// The glTF scene's name.
    pub scene: String,
    /// Metres per model unit, for glTF.
    pub metres: f32,
}

/// The frames' meshes taken together ([`Format::frame_meshes`]).
pub(crate) trait MeshSeries: Send {
    /// Takes the mesh of the frame at `position` in the stream, in order.
    ///
    /// # Errors
    /// When the mesh cannot be taken or a file written.
    fn push(&mut self, mesh: &Mesh, position: usize) -> Result<()>;

    /// Ends the series; returns the paths of its files.
    ///
    /// # Errors
    /// When a file cannot be written.
    fn finish(self: Box<Self>) -> Result<Vec<PathBuf>>;
}

/// A mesh streamed a piece at a time ([`Format::mesh_stream`]).
pub(crate) trait MeshStream {
    /// Takes the next piece: its faces in a group with a material, and
    /// its vertices coloured as the material.
    ///
    /// # Errors
    /// When a file cannot be written.
    fn piece(&mut self, piece: &Mesh) -> Result<()>;

    /// Ends the mesh; returns the paths of its files.
    ///
    /// # Errors
    /// When a file cannot be written.
    fn finish(self: Box<Self>) -> Result<Vec<PathBuf>>;
}

/// What a streamed mesh is ([`Format::mesh_stream`]).
#[derive(Debug)]
pub(crate) struct StreamedMesh<'a> {
    /// Its files' stem (`plant`).
    pub stem: &'a str,
    /// What it is, for a note (`the plant's last frame`).
    pub what: &'a str,
    /// Its first comment line.
    pub comment: &'a str,
    /// Every material its pieces use.
    pub materials: &'a Mesh,
    /// How its text is printed, where the format is text.
    pub style: ObjStyle,
    /// The most vertices a format that holds the whole mesh in memory
    /// takes before it writes none.
    pub max_vertices: usize,
}

/// A kind of output file: its name for `--only`, whether a run writes it
/// unasked, and its format.
pub(crate) struct Kind {
    /// The name `--only` knows it by.
    pub name: &'static str,
    /// What its files are, for `--help`.
    pub about: &'static str,
    /// Whether a run without `--only` writes it.
    pub by_default: bool,
    /// How it writes what it takes.
    pub format: &'static dyn Format,
}

/// Every kind, in the order `--only` lists them (at most 16).
pub(crate) const KINDS: [Kind; 8] = [
    png::KIND,
    obj::KIND,
    glb::KIND,
    anim::KIND,
    svg::KIND,
    csv::KIND,
    jsonl::KIND,
    plot::KIND,
];

/// The kinds of output file a run writes (`stream.bin` always, and the
/// small text summaries `summary.txt` and `mask.pbm` with any kind).
#[derive(Clone, Copy, PartialEq, Eq)]
pub struct Kinds(u16);

impl fmt::Debug for Kinds {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = self.iter().map(|k| k.name).collect();
        write!(f, "Kinds({})", names.join(","))
    }
}

impl Kinds {
    /// The kinds of a run without `--only`.
    pub const DEFAULT: Kinds = {
        let mut bits = 0;
        let mut k = 0;
        while k < KINDS.len() {
            if KINDS[k].by_default {
                bits |= 1 << k;
            }
            k += 1;
        }
        Kinds(bits)
    };

    /// The kinds of a comma-separated list (`png,obj`).
    ///
    /// # Errors
    /// When a name is not a kind's (the error lists the allowed ones) or
    /// the list is empty.
    pub fn parse(list: &str) -> Result<Kinds> {
        let mut bits = 0u16;
        for name in list.split(',').map(str::trim).filter(|n| !n.is_empty()) {
            let Some(k) = KINDS.iter().position(|k| k.name == name) else {
                let allowed: Vec<&str> = KINDS.iter().map(|k| k.name).collect();
                bail!(
                    "--only: unknown output kind '{name}' (allowed: {})",
                    allowed.join(", ")
                );
            };
            bits |= 1 << k;
        }
        if bits == 0 {
            bail!("--only needs at least one output kind");
        }
        Ok(Kinds(bits))
    }

    /// The help of `--only`: every kind, what its files are, and the
    /// default.
    #[must_use]
    pub fn help() -> String {
        let mut help = String::from("Write only these kinds of file, a comma list of");
        for (k, kind) in KINDS.iter().enumerate() {
            let sep = if k + 1 == KINDS.len() {
                " and"
            } else if k > 0 {
                ","
            } else {
                ""
            };
            help.push_str(&format!("{sep} {} ({})", kind.name, kind.about));
        }
        let unasked: Vec<&str> = KINDS
            .iter()
            .filter(|k| !k.by_default)
            .map(|k| k.name)
            .collect();
        help.push_str(&format!(
            "; stream.bin and summary.txt are always written. Default: all of them but {}.",
            unasked.join(", ")
        ));
        help
    }

    /// The kinds chosen, in [`KINDS`]' order.
    fn iter(self) -> impl Iterator<Item = &'static Kind> {
        KINDS
            .iter()
            .enumerate()
            .filter(move |(k, _)| self.0 & (1 << k) != 0)
            .map(|(_, kind)| kind)
    }

    /// The formats of the kinds chosen that take `product`.
    pub(crate) fn formats(self, product: Product) -> impl Iterator<Item = &'static dyn Format> {
        self.iter()
            .map(|k| k.format)
            .filter(move |f| f.takes(product))
    }

    /// Whether a kind chosen takes `product`: whether to make it.
    #[must_use]
    pub fn wants(self, product: Product) -> bool {
        self.formats(product).next().is_some()
    }

    /// Writes `chart` as every kind chosen that takes charts (`STEM.png`,
    /// `STEM.svg`), `size` pixels; returns the paths.
    ///
    /// # Errors
    /// A file that cannot be written, or a chart that cannot be drawn.
    pub(crate) fn chart(
        self,
        chart: &Chart,
        dir: &Path,
        stem: &str,
        size: (u32, u32),
    ) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        for f in self.formats(Product::Chart) {
            written.extend(f.chart(chart, dir, stem, size)?);
        }
        Ok(written)
    }

    /// Writes a table (`STEM.csv`) by `write`, which writes it at the
    /// path given; returns the paths.
    ///
    /// # Errors
    /// When `write` fails.
    pub(crate) fn table(
        self,
        dir: &Path,
        stem: &str,
        mut write: impl FnMut(&Path) -> Result<()>,
    ) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        for f in self.formats(Product::Table) {
            written.extend(f.table(dir, stem, &mut write)?);
        }
        Ok(written)
    }

    /// Writes a picture of `product` (a frame's or the run's, `STEM.png`)
    /// by `save`, which saves it as a PNG at the path given; returns the
    /// paths.
    ///
    /// # Errors
    /// When `save` fails.
    pub(crate) fn picture(
        self,
        product: Product,
        dir: &Path,
        stem: &str,
        mut save: impl FnMut(&Path) -> Result<()>,
    ) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        for f in self.formats(product) {
            written.extend(f.picture(dir, stem, &mut save)?);
        }
        Ok(written)
    }

    /// Writes a mesh of the run (`STEM.obj` and its library); returns
    /// the paths.
    ///
    /// # Errors
    /// When a file cannot be written.
    pub(crate) fn mesh(
        self,
        mesh: &Mesh,
        dir: &Path,
        stem: &str,
        style: ObjStyle,
    ) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        for f in self.formats(Product::Mesh) {
            written.extend(f.mesh(mesh, dir, stem, style)?);
        }
        Ok(written)
    }

    /// Starts a streamed mesh of the run (a mesh, a scene of one frame)
    /// in every kind chosen that takes meshes.
    ///
    /// # Errors
    /// When a file cannot be started.
    pub(crate) fn mesh_streams(
        self,
        dir: &Path,
        stream: &StreamedMesh<'_>,
    ) -> Result<Vec<Box<dyn MeshStream>>> {
        let mut streams = Vec::new();
        let meshes = |f: &&dyn Format| f.takes(Product::Mesh) || f.takes(Product::FrameMeshes);
        for f in self.iter().map(|k| k.format).filter(meshes) {
            streams.extend(f.mesh_stream(dir, stream)?);
        }
        Ok(streams)
    }

    /// Writes `drawing` into `dir` (`plot.svg`); returns the paths.
    ///
    /// # Errors
    /// When a file cannot be written.
    pub(crate) fn drawing(self, drawing: &Drawing, dir: &Path) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        for f in self.formats(Product::Drawing) {
            written.extend(f.drawing(drawing, dir)?);
        }
        Ok(written)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_parse_and_name_the_allowed_ones() {
        let k = Kinds::parse("png,glb").unwrap();
        let names = |k: Kinds| k.iter().map(|k| k.name).collect::<Vec<_>>().join(",");
        assert_eq!(names(k), "png,glb");
        assert!(
            k.wants(Product::Chart) && k.wants(Product::FrameMeshes) && !k.wants(Product::Table)
        );
        let e = Kinds::parse("png,gif").unwrap_err().to_string();
        assert!(
            e.contains("'gif'") && e.contains("png, obj, glb, anim, svg, csv, jsonl, plot"),
            "{e}"
        );
        assert_eq!(names(Kinds::DEFAULT), "png,obj,glb,anim,svg,csv,jsonl");
        assert!(Kinds::parse("plot").unwrap().wants(Product::Drawing));
    }

    /// Each product goes to the kinds `--help` promises it to.
    #[test]
    fn each_product_goes_to_its_kinds() {
        use Product::*;
        let takers = |p: Product| -> Vec<&str> {
            let takes = |k: &&Kind| k.format.takes(p);
            KINDS.iter().filter(takes).map(|k| k.name).collect()
        };
        let routes = [
            (FrameMesh, "obj"),
            (FrameMeshes, "obj,glb"),
            (FramePicture, "png"),
            (Animation, "anim"),
            (Picture, "png"),
            (Mesh, "obj"),
            (Chart, "png,svg"),
            (Table, "csv"),
            (Drawing, "plot"),
            (Records, "jsonl"),
        ];
        for (p, kinds) in routes {
            assert_eq!(takers(p).join(","), kinds, "{p:?}");
        }
    }
}
