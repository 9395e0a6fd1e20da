//! The host's memory is not bounded by the stream. `run --grammar` of
//! ABOP's shrub streams into its file and draws from it; a counting
//! allocator sees every heap byte of the library doing it. Beyond the
//! plant's picture (its RGBA canvas, the RGB copy the PNG encoder takes,
//! the compressed bytes), the peak heap stays far below the stream and
//! does not grow with it.

#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::panic,
    reason = "a test stops at the first thing that is not as it expects"
)]
#![allow(unsafe_code, reason = "a global allocator that counts the heap")]

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use morphogen_cli::exec;
use morphogen_cli::outputs::{Kinds, plant};

/// The system allocator, counting the bytes live and their peak.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

fn grew(bytes: usize) {
    let now = LIVE.fetch_add(bytes, Ordering::SeqCst) + bytes;
    PEAK.fetch_max(now, Ordering::SeqCst);
}

// SAFETY: every call goes to `System` with the caller's arguments; the
// counters only watch.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as `GlobalAlloc::alloc`, which the caller upholds.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        // SAFETY: as `GlobalAlloc::alloc_zeroed`, which the caller upholds.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from this allocator with `layout`.
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as `GlobalAlloc::realloc`, which the caller upholds.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            // Both blocks are live while the bytes move.
            grew(new_size);
            LIVE.fetch_sub(layout.size(), Ordering::SeqCst);
        }
        p
    }
}

#[global_allocator]
static HEAP: Counting = Counting;

/// What one run of the shrub at `n` derivations cost.
struct Cost {
    /// The stream file's size.
    stream: usize,
    /// The peak heap above what was live before the run.
    peak: usize,
    /// The heap its picture needs: canvas, RGB copy and PNG bytes.
    picture: usize,
}

fn shrub(n: u32, dir: &Path) -> Cost {
    let text = include_str!("../../grammars/abop-shrub.lsys")
        .replace("\nn = 7\n", &format!("\nn = {n}\n"));
    assert!(text.contains(&format!("\nn = {n}\n")));
    let out = dir.join(format!("shrub-{n}"));
    std::fs::create_dir_all(&out).unwrap();
    let before = LIVE.load(Ordering::SeqCst);
    PEAK.store(before, Ordering::SeqCst);
    let run = exec::run_grammar(
        Path::new("shrub.lsys"),
        &text,
        0,
        4096,
        exec::RunPaths {
            stream: &out.join(exec::STREAM_FILE),
            jsonl: Some(&out.join(exec::JSONL_FILE)),
        },
        false,
    )
    .unwrap();
    let written = exec::write_outputs(&out, &run, false, |records, dir| {
        plant::write(records, dir, Kinds::DEFAULT)
    })
    .unwrap();
    let peak = PEAK.load(Ordering::SeqCst) - before;
    // stream.bin, records.jsonl, plant.png, plant.obj, plant.mtl,
    // segments.csv, and model.glb for a plant of at most
    // plant::GLB_MAX_VERTICES vertices.
    let glb = out.join("model.glb").exists();
    assert_eq!(written.len(), 6 + usize::from(glb));
    let png = std::fs::read(out.join("plant.png")).unwrap();
    // The PNG's IHDR: width and height, big-endian, from byte 16.
    let side = |at: usize| u32::from_be_bytes(png[at..at + 4].try_into().unwrap()) as usize;
    let pixels = side(16) * side(20);
    Cost {
        stream: std::fs::metadata(out.join("stream.bin")).unwrap().len() as usize,
        peak,
        picture: pixels * (4 + 3) + png.len(),
    }
}

#[test]
fn the_shrub_draws_from_its_stream_file_in_bounded_memory() {
    let dir = tempfile::tempdir().unwrap();
    let small = shrub(7, dir.path());
    let large = shrub(10, dir.path());
    let mib = |b: usize| b as f64 / f64::from(1 << 20);
    let report = format!(
        "n = 7: stream {:.2} MiB, peak heap {:.2} MiB (picture {:.2}); n = 10: stream {:.2} MiB, peak heap {:.2} MiB (picture {:.2})",
        mib(small.stream),
        mib(small.peak),
        mib(small.picture),
        mib(large.stream),
        mib(large.peak),
        mib(large.picture)
    );
    eprintln!("{report}");
    // 30 times the stream: holding it, its records or the plant's items
    // would show here (the stream alone is 8 MiB).
    assert!(large.stream > 28 * small.stream, "{report}");
    let rest = large.peak.saturating_sub(large.picture);
    assert!(rest < large.stream / 4, "{report}");
    assert!(
        large.peak < small.peak + (2 << 20),
        "the peak grows with the stream: {report}"
    );
    // The large shrub is past the glTF budget: no model.glb, whose mesh
    // would be held whole.
    assert!(!dir.path().join("shrub-10/model.glb").exists());
    // The runs of the depth sort went where they were spilled, and away.
    let left: Vec<_> = std::fs::read_dir(dir.path().join("shrub-10"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 6, "{left:?}");
}
