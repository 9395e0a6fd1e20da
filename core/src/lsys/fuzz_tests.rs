//! A stable-Rust stand-in for the cargo-fuzz target (`core/fuzz/`): feeds
//! mutated grammars to the parser and, when they parse, derives and draws
//! a bounded prefix. Nothing may panic; errors must be located.
//!
//! `LSYS_FUZZ_ITERATIONS` sets the number of inputs (default 2 000; the
//! long run quoted in the docs used 2 000 000).

use std::string::String;
use std::vec::Vec;

use super::tests::ALL;
use super::*;
use crate::Error;
use crate::rng::KeyedRng;
use crate::sim::{Simulation, Start};
use crate::stream::{Record, Sink, SinkError};

/// Bytes the mutator inserts: the format's punctuation, digits, letters.
const ALPHABET: &[u8] =
    b"FfGgABLSX+-&^\\/|$[]{}.!'()<>:,#=*0123456789.  \n\nnxyaxiomignoredelta_^~%%%@?;~L~P";

/// Counts records, refusing more than a budget (bounds the run time).
struct Budget(u32);

impl Sink for Budget {
    fn record(&mut self, _: &Record) -> Result<(), SinkError> {
        if self.0 == 0 {
            return Err(SinkError::Full { capacity: 0 });
        }
        self.0 -= 1;
        Ok(())
    }
}

fn mutate(rng: &mut KeyedRng, seed: &[u8]) -> Vec<u8> {
    let mut v = seed.to_vec();
    for _ in 0..=rng.below(8) {
        let at = rng.below(v.len() as u32 + 1) as usize;
        match rng.below(5) {
            0 if at < v.len() => {
                v.remove(at);
            }
            1 if at < v.len() => v[at] = ALPHABET[rng.below(ALPHABET.len() as u32) as usize],
            2 => v.insert(at, ALPHABET[rng.below(ALPHABET.len() as u32) as usize]),
            3 => {
                // Duplicate a random slice (grows nesting and lengths).
                let end = (at + rng.below(24) as usize).min(v.len());
                let piece: Vec<u8> = v[at..end].to_vec();
                for (k, b) in piece.into_iter().enumerate() {
                    v.insert(at + k, b);
                }
            }
            _ => v.insert(at, rng.next_u32() as u8), // any byte, UTF-8 or not
        }
    }
    v
}

/// Runs one input: parse, then at most a budget of records.
pub(crate) fn exercise(bytes: &[u8]) {
    let text = String::from_utf8_lossy(bytes);
    let mut sim = LSystem::new();
    match sim.start(&text, 1) {
        Err(Error::Lsys(LsysError::Parse(e))) => {
            let lines = text.split('\n').count() as u32;
            assert!(e.line >= 1 && e.line <= lines.max(1), "{e} in {text:?}");
            assert!(e.column >= 1, "{e}");
        }
        Err(e) => panic!("load gave {e}"),
        Ok(()) => {
            let mut sink = Budget(3000);
            for _ in 0..200 {
                match sim.step(&mut sink) {
                    Ok(p) if p.finished() => break,
                    Ok(_) => {}
                    Err(_) => break,
                }
            }
        }
    }
}

#[test]
fn mutated_grammars_never_panic() {
    let iterations: u32 = std::env::var("LSYS_FUZZ_ITERATIONS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(2000);
    let mut seeds: Vec<&[u8]> = ALL.iter().map(|(_, g)| g.as_bytes()).collect();
    let extra = [
        "n = 3\nignore: +-\naxiom: b[a]a+a\nb < a > a -> b\nb -> a\n".as_bytes(),
        b"n = 4\naxiom: F A\nA -> (1) [+F%F]F A\nA -> (2) F[-A%]%A\n",
        b"n = 3\ntropism = 0, -1, 0\nelasticity = 0.3\naxiom: A\nA -> F[+~L(0.5)][-~P]A\nA -> I\ndecomposition:\nI -> J J\ninterpretation:\nJ -> F[&F]\n",
        b"n=2\nk=2\naxiom: A(1,2)\nA(x,y) : x>=1 || y<0 -> (k*0.5) A(x^2, y/0)[+(sin(x))F(y)]\n",
    ];
    seeds.extend(extra);
    let mut rng = KeyedRng::new(2026, 2);
    for i in 0..iterations {
        let seed = seeds[(i as usize) % seeds.len()];
        let input = mutate(&mut rng, seed);
        exercise(&input);
    }
}
