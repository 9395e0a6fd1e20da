//! The kinds of output file `morphogen run` writes, as `--only` selects
//! them. A model states its products ([`Product`]: a frame's mesh, a
//! chart of the run, a table…); each kind, in a module of its own, says
//! which products it takes and writes them in its format (`Format`);
//! `KINDS` lists them, and `ALWAYS` the formats written with any kind (a
//! run's summary, a mask). A new kind of file is a new module here and
//! its line in `KINDS` (or `ALWAYS`): the models and the driver hand it
//! their products unchanged.

use std::borrow::Cow;
use std::fmt;
use std::path::{Path, PathBuf};

use anyhow::{Result, bail};

use super::chart::Chart;
use super::mesh::{Mesh, ObjStyle};
use super::picture::pack_rgb;
use super::plot::Drawing;

mod anim;
mod csv;
mod glb;
mod jsonl;
mod obj;
mod pbm;
mod plot;
mod png;
mod svg;
mod txt;

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
    /// A text of the run (`summary.txt`), written with any kind.
    Text,
    /// A 1-bit picture of the run (a mosaic's control mask, `mask.pbm`),
    /// written with any kind.
    Bitmap,
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

    /// Writes `text` as `dir/stem.*`.
    ///
    /// # Errors
    /// When the file cannot be written.
    fn text(&self, _text: &str, _dir: &Path, _stem: &str) -> Result<Option<PathBuf>> {
        Ok(None)
    }

    /// Writes `pixels` as `dir/stem.*`.
    ///
    /// # Errors
    /// When the file cannot be written.
    fn picture(&self, _pixels: &Pixels<'_>, _dir: &Path, _stem: &str) -> Result<Option<PathBuf>> {
        Ok(None)
    }

    /// Starts what takes the frames' pictures in sequence, into `dir`.
    ///
    /// # Errors
    /// When a file cannot be started.
    fn animation(
        &self,
        _dir: &Path,
        _sequence: &Sequence,
    ) -> Result<Option<Box<dyn PictureSeries>>> {
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

/// A picture's pixels, row by row.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Pixels<'a> {
    /// Red, green and blue bytes of each pixel.
    Rgb {
        /// Pixels across and down.
        size: (u32, u32),
        /// The bytes.
        rgb: &'a [u8],
    },
    /// An index into `palette` for each pixel, a byte each.
    Indexed {
        /// Pixels across and down.
        size: (u32, u32),
        /// The colours indexed.
        palette: &'a [[u8; 3]],
        /// The indices.
        indices: &'a [u8],
    },
    /// A bit for each pixel, 1 white and 0 black, eight to a byte from
    /// the high bit, each row from a byte of its own (a mosaic's mask).
    Bits {
        /// Pixels across and down.
        size: (u32, u32),
        /// The rows' bytes.
        bits: &'a [u8],
    },
}

impl<'a> Pixels<'a> {
    /// Pixels across and down.
    pub(crate) fn size(&self) -> (u32, u32) {
        match *self {
            Pixels::Rgb { size, .. } | Pixels::Indexed { size, .. } | Pixels::Bits { size, .. } => {
                size
            }
        }
    }

    /// Red, green and blue bytes of each pixel: an index past the palette
    /// is black, and so is a bit past the rows' bytes.
    pub(crate) fn rgb(&self) -> Cow<'a, [u8]> {
        let (palette, indices) = match *self {
            Pixels::Rgb { rgb, .. } => return Cow::Borrowed(rgb),
            Pixels::Indexed {
                palette, indices, ..
            } => (palette, indices),
            Pixels::Bits { size: (w, h), bits } => {
                return Cow::Owned(white_bits(bits, w as usize, h as usize));
            }
        };
        // Every index a byte can hold: its RGB in the low three bytes of
        // a little-endian word.
        let mut colour = [0u32; 256];
        for (c, p) in colour.iter_mut().zip(palette) {
            *c = u32::from_le_bytes([p[0], p[1], p[2], 0]);
        }
        let word = |i: &u8| colour[usize::from(*i)];
        let mut rgb = vec![0; 3 * indices.len()];
        let (fours, rest) = indices.as_chunks::<4>();
        let (out, out_rest) = rgb.as_chunks_mut::<12>();
        for (out, four) in out.iter_mut().zip(fours) {
            *out = pack_rgb(four.each_ref().map(word));
        }
        for (out, i) in out_rest.as_chunks_mut::<3>().0.iter_mut().zip(rest) {
            let [r, g, b, _] = word(i).to_le_bytes();
            *out = [r, g, b];
        }
        Cow::Owned(rgb)
    }
}

/// The RGB bytes of `w` × `h` pixels of [`Pixels::Bits`]: white for 1.
fn white_bits(bits: &[u8], w: usize, h: usize) -> Vec<u8> {
    let stride = w.div_ceil(8);
    let mut rgb = Vec::with_capacity(3 * w * h);
    for y in 0..h {
        for x in 0..w {
            let byte = bits.get(y * stride + x / 8).copied().unwrap_or(0);
            let white = (byte >> (7 - x % 8)) & 1 == 1;
            rgb.extend([if white { 255 } else { 0 }; 3]);
        }
    }
    rgb
}

/// The frames' pictures in sequence ([`Format::animation`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Sequence {
    /// Each picture's size, pixels.
    pub size: (u32, u32),
    /// The palette of indexed pictures, if they are.
    pub palette: Option<Vec<[u8; 3]>>,
    /// How many pictures.
    pub frames: usize,
}

/// The frames' pictures taken in sequence ([`Format::animation`]).
pub(crate) trait PictureSeries: Send + Sync {
    /// Takes the picture at `slot` in the sequence and its label, from
    /// any drawing worker in any order.
    ///
    /// # Errors
    /// When the picture cannot be taken or a file written.
    fn frame(&self, slot: usize, pixels: &Pixels<'_>, label: &str) -> Result<()>;

    /// Ends the sequence; returns the paths of its files.
    ///
    /// # Errors
    /// When a picture is missing or a file cannot be written.
    fn finish(self: Box<Self>) -> Result<Vec<PathBuf>>;
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

/// The formats of the products written with any kind, which `--only`
/// has no name for: texts and 1-bit pictures of the run.
const ALWAYS: [&dyn Format; 2] = [txt::FORMAT, pbm::FORMAT];

/// The kinds of output file a run writes (`stream.bin` always, and the
/// `ALWAYS` formats' `summary.txt` and `mask.pbm` with any kind).
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
            "; stream.bin, summary.txt and a masked mosaic's mask.pbm are always written. Default: all of them but {}.",
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

    /// The formats of the kinds chosen, and those written with any
    /// ([`ALWAYS`]), that take `product`.
    pub(crate) fn formats(self, product: Product) -> impl Iterator<Item = &'static dyn Format> {
        self.iter()
            .map(|k| k.format)
            .chain(ALWAYS)
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

    /// Writes `text`, a text of the run, as `STEM.txt`; returns the
    /// paths.
    ///
    /// # Errors
    /// When a file cannot be written.
    pub(crate) fn text(self, text: &str, dir: &Path, stem: &str) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        for f in self.formats(Product::Text) {
            written.extend(f.text(text, dir, stem)?);
        }
        Ok(written)
    }

    /// Writes `pixels`, a picture of `product` (a frame's or the run's),
    /// as `STEM.png` (a 1-bit one as `STEM.pbm`); returns the paths.
    ///
    /// # Errors
    /// When a file cannot be written.
    pub(crate) fn picture(
        self,
        product: Product,
        pixels: &Pixels<'_>,
        dir: &Path,
        stem: &str,
    ) -> Result<Vec<PathBuf>> {
        let mut written = Vec::new();
        for f in self.formats(product) {
            written.extend(f.picture(pixels, dir, stem)?);
        }
        Ok(written)
    }

    /// Starts the frames' pictures in sequence (`animation.png`) in
    /// every kind chosen that takes them.
    ///
    /// # Errors
    /// When a file cannot be started.
    pub(crate) fn animations(
        self,
        dir: &Path,
        sequence: &Sequence,
    ) -> Result<Vec<Box<dyn PictureSeries>>> {
        let mut series = Vec::new();
        for f in self.formats(Product::Animation) {
            series.extend(f.animation(dir, sequence)?);
        }
        Ok(series)
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

    /// Indexed pixels read as their palette's colours, four at a time
    /// and one by one, black past the palette; RGB pixels as they are.
    #[test]
    fn pixels_read_as_rgb() {
        let palette = [[1, 2, 3], [4, 5, 6]];
        let indices = [0, 1, 1, 0, 7];
        let indexed = Pixels::Indexed {
            size: (5, 1),
            palette: &palette,
            indices: &indices,
        };
        let rgb = [1, 2, 3, 4, 5, 6, 4, 5, 6, 1, 2, 3, 0, 0, 0];
        assert_eq!(*indexed.rgb(), rgb);
        let same = Pixels::Rgb {
            size: (5, 1),
            rgb: &rgb,
        };
        assert!(matches!(same.rgb(), Cow::Borrowed(b) if b == rgb));
        assert_eq!((indexed.size(), same.size()), ((5, 1), (5, 1)));
        // Two rows of 9: each row from a byte of its own, the last bit
        // past the bytes.
        let bits = Pixels::Bits {
            size: (9, 2),
            bits: &[0b1000_0001, 0b1000_0000, 0b0100_0000],
        };
        let white: Vec<bool> = bits.rgb().iter().step_by(3).map(|&v| v == 255).collect();
        // The rows one after the other.
        let expected: Vec<bool> = "100000011010000000".chars().map(|c| c == '1').collect();
        assert_eq!((white, bits.size()), (expected, (9, 2)));
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
        let always = |p: Product| ALWAYS.iter().filter(|f| f.takes(p)).count();
        for (p, kinds) in routes {
            assert_eq!((takers(p).join(","), always(p)), (kinds.into(), 0), "{p:?}");
        }
        // A text and a 1-bit picture go to no kind `--only` names, and
        // are written with any.
        let only = Kinds::parse("jsonl").unwrap();
        for p in [Text, Bitmap] {
            assert!(
                takers(p).is_empty() && always(p) == 1 && only.wants(p),
                "{p:?}"
            );
        }
    }
}
