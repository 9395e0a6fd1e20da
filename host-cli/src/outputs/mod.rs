//! The model's natural files written by `morphogen run`: pictures, meshes,
//! tables. Each model has a module; [`write()`] picks it by the preset's
//! model. Writers read their records in passes over a [`Records`] source
//! (the stream file, read back frame by frame), one frame or day at a
//! time, so their memory is that of a frame and a picture, never that of
//! the stream.

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, mpsc};

use anyhow::{Result, anyhow};
use morphogen::preset::{Model, Preset};

use crate::records::Records;

pub mod animation;
pub mod body;
pub mod bones;
pub mod chart;
pub mod curve;
pub mod horn;
pub mod mesh;
pub mod mosaic;
pub mod picture;
pub mod plant;
pub mod plot;
pub mod raster;
pub mod text;

/// Writes the files natural to `preset`'s model into `dir`; returns their
/// paths.
///
/// # Errors
/// When the records cannot be read or a file cannot be written.
pub fn write<R: Records + ?Sized>(
    preset: &Preset<'_>,
    records: &R,
    dir: &Path,
) -> Result<Vec<PathBuf>> {
    match preset.model {
        Model::GrowthCurve(_) => curve::write(records, dir),
        Model::Horn(p) => horn::write(records, dir, p.rings_per_module),
        Model::LSystem(_) => plant::write(records, dir),
        Model::Body(p) => {
            let binding = morphogen::body::binding_summary::<
                { morphogen_scenario::body_files::USER_CYLINDERS },
            >(p.model, p.table)
            .ok();
            body::write(preset.name, records, dir, binding)
        }
        Model::Bones(p) => bones::write(preset.name, p, records, dir),
        Model::Mosaic(p) => mosaic::write(p, records, dir),
        _ => Ok(Vec::new()),
    }
}

/// Runs `work` on every item `produce` hands to its sender, on rayon's
/// number of threads, while `produce` goes on reading: at most two items
/// a thread are in hand at once. Returns the results in the order the
/// items were handed over, or the first error (of `produce`, else of the
/// first item that failed).
pub(crate) fn pipeline<T, R>(
    produce: impl FnOnce(&mut dyn FnMut(T) -> Result<()>) -> Result<()>,
    work: impl Fn(T) -> Result<R> + Sync,
) -> Result<Vec<R>>
where
    T: Send,
    R: Send,
{
    let threads = rayon::current_num_threads().max(1);
    let (jobs, queue) = mpsc::sync_channel::<(usize, T)>(threads);
    // Shared by the workers: when the last one stops, sending fails.
    let queue = Arc::new(Mutex::new(queue));
    let (done, results) = mpsc::channel::<(usize, Result<R>)>();
    let work = &work;
    std::thread::scope(|scope| {
        for _ in 0..threads {
            let queue = Arc::clone(&queue);
            let done = done.clone();
            scope.spawn(move || {
                loop {
                    let job = match queue.lock() {
                        Ok(queue) => queue.recv(),
                        Err(_) => return,
                    };
                    let Ok((i, item)) = job else { return };
                    if done.send((i, work(item))).is_err() {
                        return;
                    }
                }
            });
        }
        drop(queue);
        drop(done);
        let mut handed = 0usize;
        let produced = produce(&mut |item| {
            jobs.send((handed, item))
                .map_err(|_| anyhow!("the output writers stopped"))?;
            handed += 1;
            Ok(())
        });
        drop(jobs);
        let mut slots: Vec<Option<Result<R>>> = Vec::new();
        slots.resize_with(handed, || None);
        for (i, result) in results {
            if let Some(slot) = slots.get_mut(i) {
                *slot = Some(result);
            }
        }
        produced?;
        slots
            .into_iter()
            .map(|slot| slot.unwrap_or_else(|| Err(anyhow!("an output writer stopped"))))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pipeline_keeps_the_order_and_reports_the_first_error() {
        let squares = pipeline(
            |send| (0..100u64).try_for_each(send),
            |i| {
                std::thread::sleep(std::time::Duration::from_micros((100 - i) * 10));
                Ok(i * i)
            },
        )
        .unwrap();
        assert_eq!(squares, (0..100u64).map(|i| i * i).collect::<Vec<_>>());
        let failed = pipeline(
            |send| (0..10u64).try_for_each(send),
            |i| {
                if i % 4 == 3 {
                    Err(anyhow!("item {i}"))
                } else {
                    Ok(i)
                }
            },
        );
        assert_eq!(failed.unwrap_err().to_string(), "item 3");
        let stopped = pipeline::<u64, u64>(
            |send| {
                send(1)?;
                Err(anyhow!("unreadable"))
            },
            Ok,
        );
        assert_eq!(stopped.unwrap_err().to_string(), "unreadable");
    }
}
