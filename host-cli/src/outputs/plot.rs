//! `plot.svg`: a model's last frame as strokes for a pen plotter. A
//! [`Drawing`] holds strokes in the model's units (x right, y up), one
//! [`Pen`] per colour; [`Drawing::save`] fits them on A4 (portrait or
//! landscape, whichever fits the drawing larger) with a [`MARGIN`], in
//! millimetres, each pen an Inkscape layer, stroked and never filled.

use std::collections::BTreeMap;
use std::path::Path;

use anyhow::{Result, bail};
use svg::Document;
use svg::node::element::path::Data;
use svg::node::element::{Group, Path as SvgPath};

use crate::atomic::write_atomic;

/// The file's name.
pub const FILE: &str = "plot.svg";

/// The paper, millimetres across and down, portrait (ISO 216 A4).
pub const A4: [f64; 2] = [210.0, 297.0];

/// The blank border round the drawing, millimetres.
pub const MARGIN: f64 = 15.0;

/// The pen's line width in the file, millimetres (a fine felt tip).
const LINE_WIDTH: f64 = 0.3;

/// The Inkscape namespace, whose layer attributes plotting tools read.
const INKSCAPE: &str = "http://www.inkscape.org/namespaces/inkscape";

/// One pen stroke: points in order, closed back to the first or not.
#[derive(Debug, Clone, PartialEq)]
pub struct Stroke {
    /// Its points, model units, y up.
    pub points: Vec<[f64; 2]>,
    /// Whether it returns to its first point.
    pub closed: bool,
}

impl Stroke {
    /// An open stroke through `points`.
    #[must_use]
    pub fn open(points: Vec<[f64; 2]>) -> Stroke {
        Stroke {
            points,
            closed: false,
        }
    }
}

/// The strokes drawn with one pen, which is one layer of the file.
#[derive(Debug, Clone, PartialEq)]
pub struct Pen {
    /// What it draws (`outline`), its layer's name after its number.
    pub name: String,
    /// Its colour on screen.
    pub colour: [u8; 3],
    /// Its strokes, in plotting order.
    pub strokes: Vec<Stroke>,
}

/// A frame as pen strokes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Drawing {
    /// The pens, in the order they plot; a pen without strokes is left out
    /// of the file.
    pub pens: Vec<Pen>,
}

/// How model units map onto the paper.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Fit {
    paper: [f64; 2],
    scale: f64,
    /// Where model (0, 0) lands, millimetres from the top left.
    origin: [f64; 2],
}

impl Fit {
    fn mm(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.origin[0] + p[0] * self.scale,
            self.origin[1] - p[1] * self.scale,
        ]
    }
}

impl Drawing {
    /// The box of every stroke's points: lowest and highest x and y.
    fn extent(&self) -> Option<([f64; 2], [f64; 2])> {
        let mut points = self
            .pens
            .iter()
            .flat_map(|p| &p.strokes)
            .flat_map(|s| &s.points);
        let first = *points.next()?;
        Some(points.fold((first, first), |(lo, hi), p| {
            (
                [lo[0].min(p[0]), lo[1].min(p[1])],
                [hi[0].max(p[0]), hi[1].max(p[1])],
            )
        }))
    }

    /// The drawing centred on A4 inside the margin, as large as fits.
    fn fit(&self) -> Result<Fit> {
        let Some((lo, hi)) = self.extent() else {
            bail!("{FILE}: the frame has nothing to draw");
        };
        if !(lo.iter().chain(&hi).all(|v| v.is_finite())) {
            bail!("{FILE}: the frame has a point that is not a number");
        }
        let span = [(hi[0] - lo[0]).max(1e-9), (hi[1] - lo[1]).max(1e-9)];
        let scale_on = |paper: [f64; 2]| {
            ((paper[0] - 2.0 * MARGIN) / span[0]).min((paper[1] - 2.0 * MARGIN) / span[1])
        };
        let (portrait, landscape) = (A4, [A4[1], A4[0]]);
        let paper = if scale_on(landscape) > scale_on(portrait) {
            landscape
        } else {
            portrait
        };
        let scale = scale_on(paper);
        let used = [span[0] * scale, span[1] * scale];
        let left = (paper[0] - used[0]) / 2.0;
        let bottom = paper[1] - (paper[1] - used[1]) / 2.0;
        Ok(Fit {
            paper,
            scale,
            origin: [left - lo[0] * scale, bottom + lo[1] * scale],
        })
    }

    /// The SVG document: millimetres on A4, a layer per pen.
    ///
    /// # Errors
    /// When there is nothing to draw or a point is not a number.
    pub fn document(&self) -> Result<Document> {
        let fit = self.fit()?;
        let [w, h] = fit.paper;
        let mut doc = Document::new()
            .set("xmlns:inkscape", INKSCAPE)
            .set("width", format!("{w}mm"))
            .set("height", format!("{h}mm"))
            .set("viewBox", (0, 0, w, h));
        let pens = self.pens.iter().filter(|p| !p.strokes.is_empty());
        for (n, pen) in pens.enumerate() {
            let [r, g, b] = pen.colour;
            let mut layer = Group::new()
                .set("id", format!("layer{}", n + 1))
                .set("inkscape:groupmode", "layer")
                .set("inkscape:label", format!("{} {}", n + 1, pen.name))
                .set("fill", "none")
                .set("stroke", format!("#{r:02x}{g:02x}{b:02x}"))
                .set("stroke-width", LINE_WIDTH)
                .set("stroke-linecap", "round")
                .set("stroke-linejoin", "round");
            for stroke in pen.strokes.iter().filter(|s| s.points.len() > 1) {
                layer = layer.add(SvgPath::new().set("d", path_data(stroke, &fit)));
            }
            doc = doc.add(layer);
        }
        Ok(doc)
    }

    /// Writes the drawing to `path` as [`Drawing::document`].
    ///
    /// # Errors
    /// When there is nothing to draw, a point is not a number, or the file
    /// cannot be written.
    pub fn save(&self, path: &Path) -> Result<()> {
        let text = self.document()?.to_string();
        write_atomic(path, format!("{text}\n").as_bytes())
    }
}

/// A stroke's path data in millimetres, to a hundredth.
fn path_data(stroke: &Stroke, fit: &Fit) -> Data {
    let at = |p: [f64; 2]| fit.mm(p).map(|v| ((v * 100.0).round() / 100.0) as f32);
    let mut points = stroke.points.iter().map(|&p| at(p));
    let mut data = Data::new();
    if let Some([x, y]) = points.next() {
        data = data.move_to((x, y));
    }
    let rest: Vec<f32> = points.flatten().collect();
    if !rest.is_empty() {
        data = data.line_to(rest);
    }
    if stroke.closed {
        data = data.close();
    }
    data
}

/// The outline of a closed triangle mesh seen along −z: every edge
/// between a face turned towards the viewer and one turned away (and
/// the open edges of faces turned towards it), joined into strokes.
/// `screen` holds the vertices in screen axes (x right, y up, z towards
/// the viewer). Parts of the outline behind the mesh are drawn too.
#[must_use]
pub fn silhouette(screen: &[[f64; 3]], triangles: &[[u32; 3]]) -> Vec<Stroke> {
    // Per edge (lower vertex first): faces turned towards and away.
    let mut faces: BTreeMap<[u32; 2], [u32; 2]> = BTreeMap::new();
    for t in triangles {
        let corner = |k: usize| screen.get(t[k] as usize);
        let (Some(a), Some(b), Some(c)) = (corner(0), corner(1), corner(2)) else {
            continue;
        };
        let turned = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
        let side = usize::from(turned <= 0.0);
        for (u, v) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            faces.entry([u.min(v), u.max(v)]).or_default()[side] += 1;
        }
    }
    let edges = faces
        .into_iter()
        .filter(|(_, [towards, away])| *towards > 0 && (*away > 0 || *towards == 1))
        .map(|(e, _)| e);
    let flat: Vec<[f64; 2]> = screen.iter().map(|p| [p[0], p[1]]).collect();
    chains(&flat, edges)
}

/// `edges` (pairs of indices into `points`) joined into as few strokes as
/// walking them allows: from each end of a branch first, then round the
/// closed loops left.
#[must_use]
pub fn chains(points: &[[f64; 2]], edges: impl IntoIterator<Item = [u32; 2]>) -> Vec<Stroke> {
    let edges: Vec<[u32; 2]> = edges
        .into_iter()
        .filter(|e| e.iter().all(|&v| (v as usize) < points.len()))
        .collect();
    let mut at: BTreeMap<u32, Vec<usize>> = BTreeMap::new();
    for (k, e) in edges.iter().enumerate() {
        at.entry(e[0]).or_default().push(k);
        at.entry(e[1]).or_default().push(k);
    }
    let mut used = vec![false; edges.len()];
    let ends: Vec<u32> = at
        .iter()
        .filter(|(_, es)| es.len() != 2)
        .map(|(&v, _)| v)
        .collect();
    let loops = edges.iter().map(|e| e[0]);
    let mut strokes = Vec::new();
    for start in ends.into_iter().chain(loops) {
        loop {
            let mut vertex = start;
            let mut walked = vec![points[start as usize]];
            while let Some(&k) = at[&vertex].iter().find(|&&k| !used[k]) {
                used[k] = true;
                let e = edges[k];
                vertex = if e[0] == vertex { e[1] } else { e[0] };
                walked.push(points[vertex as usize]);
            }
            if walked.len() < 2 {
                break;
            }
            let closed = vertex == start && walked.len() > 2;
            if closed {
                walked.pop();
            }
            strokes.push(Stroke {
                points: walked,
                closed,
            });
        }
    }
    strokes
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Drawing {
        Drawing {
            pens: vec![
                Pen {
                    name: "outline".into(),
                    colour: [0, 0, 0],
                    strokes: vec![Stroke {
                        points: vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]],
                        closed: true,
                    }],
                },
                Pen {
                    name: "rings".into(),
                    colour: [200, 20, 20],
                    strokes: vec![Stroke::open(vec![[1.0, 0.0], [1.0, 1.0]])],
                },
                Pen {
                    name: "unused".into(),
                    colour: [0, 0, 255],
                    strokes: Vec::new(),
                },
            ],
        }
    }

    #[test]
    fn a_drawing_is_millimetres_on_a4_a_layer_per_pen_never_filled() {
        let text = square().document().unwrap().to_string();
        // Twice as wide as high: landscape, 267 mm across inside the margin.
        assert!(text.contains(r#"width="297mm""#) && text.contains(r#"height="210mm""#));
        assert!(text.contains(r#"viewBox="0 0 297 210""#), "{text}");
        assert!(text.contains(&format!(r#"xmlns:inkscape="{INKSCAPE}""#)));
        assert_eq!(text.matches(r#"inkscape:groupmode="layer""#).count(), 2);
        assert!(text.contains(r#"inkscape:label="1 outline""#));
        assert!(text.contains(r#"inkscape:label="2 rings""#));
        assert_eq!(text.matches(r#"fill="none""#).count(), 2);
        assert!(!text.contains("fill=\"#") && !text.contains("<rect"));
        assert_eq!(text.matches("<path").count(), 2);
        assert!(
            text.contains(r#"d="M15,171.75 L282,171.75,282,38.25,15,38.25 z""#),
            "{text}"
        );
        assert!(text.contains(r#"d="M148.5,171.75 L148.5,38.25""#), "{text}");
    }

    #[test]
    fn a_tall_drawing_stays_portrait_and_an_empty_one_is_an_error() {
        let mut tall = square();
        tall.pens[0].strokes[0] = Stroke::open(vec![[0.0, 0.0], [0.0, 5.0]]);
        tall.pens.truncate(1);
        let text = tall.document().unwrap().to_string();
        assert!(text.contains(r#"width="210mm""#) && text.contains(r#"height="297mm""#));
        assert!(text.contains(r#"d="M105,282 L105,15""#), "{text}");
        let e = Drawing::default().document().unwrap_err().to_string();
        assert!(e.contains("nothing to draw"), "{e}");
    }

    #[test]
    fn a_cube_seen_along_a_diagonal_has_a_hexagon_for_outline() {
        // The unit cube's corners turned so that the view is along its
        // diagonal: the outline is one closed stroke of six corners.
        let corners: Vec<[f64; 3]> = (0..8)
            .map(|i| {
                [
                    f64::from(i & 1),
                    f64::from(i >> 1 & 1),
                    f64::from(i >> 2 & 1),
                ]
            })
            .map(|[x, y, z]| {
                let s = [x - 0.5, y - 0.5, z - 0.5];
                let (r2, r6, r3) = (2f64.sqrt(), 6f64.sqrt(), 3f64.sqrt());
                [
                    (s[0] - s[1]) / r2,
                    (s[0] + s[1] - 2.0 * s[2]) / r6,
                    (s[0] + s[1] + s[2]) / r3,
                ]
            })
            .collect();
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        let triangles: Vec<[u32; 3]> = quads
            .iter()
            .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
            .collect();
        let outline = silhouette(&corners, &triangles);
        assert_eq!(outline.len(), 1);
        assert!(outline[0].closed);
        assert_eq!(outline[0].points.len(), 6);
    }

    #[test]
    fn chains_walk_branches_from_their_ends_and_close_loops() {
        let p: Vec<[f64; 2]> = (0..7).map(|i| [f64::from(i), 0.0]).collect();
        // A path 0-1-2, and a triangle 3-4-5; 6 alone.
        let strokes = chains(&p, [[1, 2], [0, 1], [3, 4], [5, 3], [4, 5], [6, 9]]);
        assert_eq!(strokes.len(), 2);
        assert_eq!(strokes[0].points, vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]);
        assert!(!strokes[0].closed);
        assert_eq!(strokes[1].points.len(), 3);
        assert!(strokes[1].closed);
    }
}
