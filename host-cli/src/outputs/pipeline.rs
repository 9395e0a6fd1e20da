//! The output writers' worker pool: items read from the stream in order,
//! worked on in parallel, their results handed back in order.

use std::sync::{Arc, Mutex, mpsc};

use anyhow::{Result, anyhow};

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
