//! The L-system peer of `scripts/bench.sh`: a grammar file of Morphogen's
//! form without parameters (`grammars/abop-shrub.lsys`) derived by the
//! `lindenmayer` crate's streaming builder and drawn by a 3D turtle in f64
//! with Morphogen's conventions (ABOP Sec. 1.5: H = +y, L = −x, U = +z; a
//! turn rotates two of the frame's axes and re-orthonormalises it).
//!
//! ```sh
//! lsystem-peer grammars/abop-shrub.lsys [N]
//! ```
//!
//! Prints the segments, polygons and polygon vertices drawn (what
//! `morphogen decode` counts as `segment`, `polygon` and `point` records)
//! and the sum of the segment ends' coordinates, so that the work is seen
//! to be done.

use std::process::ExitCode;

use lindenmayer::LSystem;

type V3 = [f64; 3];

fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

fn scale(a: V3, s: f64) -> V3 {
    [a[0] * s, a[1] * s, a[2] * s]
}

fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The turtle's state, pushed by `[` and popped by `]`.
#[derive(Clone, Copy)]
struct State {
    position: V3,
    heading: V3,
    left: V3,
    up: V3,
    width: f64,
    colour: u16,
}

/// Rotates a towards b by the angle of cosine c and sine s.
fn rotate(a: &mut V3, b: &mut V3, c: f64, s: f64) {
    let (x, y) = (*a, *b);
    *a = add(scale(x, c), scale(y, s));
    *b = add(scale(y, c), scale(x, -s));
}

/// One Newton step towards unit length for H, L orthogonal to H and unit,
/// U = H × L, as Morphogen's turtle does after each turn.
fn orthonormalise(t: &mut State) {
    let h = scale(t.heading, (3.0 - dot(t.heading, t.heading)) * 0.5);
    let l = add(t.left, scale(h, -dot(h, t.left)));
    let l = scale(l, (3.0 - dot(l, l)) * 0.5);
    t.heading = h;
    t.left = l;
    t.up = cross(h, l);
}

/// A grammar file's settings and rules.
struct Grammar {
    n: usize,
    delta: f64,
    step: f64,
    width: f64,
    thin: f64,
    axiom: String,
    rules: Vec<(char, String)>,
}

fn parse(text: &str) -> Result<Grammar, String> {
    let mut g = Grammar {
        n: 0,
        delta: 0.0,
        step: 1.0,
        width: 1.0,
        thin: 1.0,
        axiom: String::new(),
        rules: Vec::new(),
    };
    for line in text.lines().map(str::trim) {
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        if let Some(axiom) = line.strip_prefix("axiom:") {
            g.axiom = axiom.trim().to_string();
        } else if let Some((lhs, rhs)) = line.split_once("->") {
            let mut symbol = lhs.trim().chars();
            match (symbol.next(), symbol.next()) {
                (Some(c), None) => g.rules.push((c, rhs.trim().replace(' ', ""))),
                _ => return Err(format!("not a rule of one symbol: {line}")),
            }
        } else if let Some((key, value)) = line.split_once('=') {
            let value: f64 = value
                .trim()
                .parse()
                .map_err(|e| format!("{line}: {e}"))?;
            match key.trim() {
                "n" => g.n = value as usize,
                "delta" => g.delta = value,
                "step" => g.step = value,
                "width" => g.width = value,
                "thin" => g.thin = value,
                other => return Err(format!("unknown setting {other}")),
            }
        } else {
            return Err(format!("not understood: {line}"));
        }
    }
    Ok(g)
}

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let Some(path) = args.next() else {
        eprintln!("usage: lsystem-peer GRAMMAR.lsys [N]");
        return ExitCode::from(2);
    };
    let g = match std::fs::read_to_string(&path)
        .map_err(|e| e.to_string())
        .and_then(|t| parse(&t))
    {
        Ok(g) => g,
        Err(e) => {
            eprintln!("{path}: {e}");
            return ExitCode::from(2);
        }
    };
    let n = args.next().and_then(|a| a.parse().ok()).unwrap_or(g.n);
    let system = LSystem::new(g.axiom.clone(), &g.rules);
    let (c, s) = (g.delta.to_radians().cos(), g.delta.to_radians().sin());
    let mut t = State {
        position: [0.0; 3],
        heading: [0.0, 1.0, 0.0],
        left: [-1.0, 0.0, 0.0],
        up: [0.0, 0.0, 1.0],
        width: g.width,
        colour: 0,
    };
    let mut stack: Vec<State> = Vec::new();
    let (mut segments, mut polygons, mut points) = (0u64, 0u64, 0u64);
    let mut polygon: Option<Vec<V3>> = None;
    let mut sum = 0.0;
    // The builder streams the derived string: it is never held whole.
    let modules: Box<dyn Iterator<Item = char>> = if n == 0 {
        Box::new(g.axiom.chars().collect::<Vec<_>>().into_iter())
    } else {
        Box::new(system.builder(n))
    };
    for m in modules {
        match m {
            'F' | 'f' => {
                let a = t.position;
                t.position = add(a, scale(t.heading, g.step));
                if let Some(p) = polygon.as_mut() {
                    p.push(t.position);
                }
                if m == 'F' {
                    segments += 1;
                    sum += a.iter().chain(&t.position).sum::<f64>() + t.width;
                }
            }
            '+' | '-' => {
                let s = if m == '-' { -s } else { s };
                rotate(&mut t.heading, &mut t.left, c, s);
                orthonormalise(&mut t);
            }
            '&' | '^' => {
                let s = if m == '^' { -s } else { s };
                rotate(&mut t.up, &mut t.heading, c, s);
                orthonormalise(&mut t);
            }
            '\\' | '/' => {
                let s = if m == '/' { -s } else { s };
                rotate(&mut t.left, &mut t.up, c, s);
                orthonormalise(&mut t);
            }
            '|' => {
                t.heading = scale(t.heading, -1.0);
                t.left = scale(t.left, -1.0);
            }
            '[' => stack.push(t),
            ']' => match stack.pop() {
                Some(saved) => t = saved,
                None => {
                    eprintln!("] without [");
                    return ExitCode::FAILURE;
                }
            },
            '{' => polygon = Some(vec![t.position]),
            '}' => {
                if let Some(mut p) = polygon.take() {
                    if p.len() > 1 && p.first() == p.last() {
                        p.pop();
                    }
                    polygons += 1;
                    points += p.len() as u64;
                }
            }
            '!' => t.width *= g.thin,
            '\'' => t.colour = t.colour.saturating_add(1),
            _ => {}
        }
    }
    println!("{segments} segments, {polygons} polygons, {points} points; sum {sum:.3}");
    ExitCode::SUCCESS
}
