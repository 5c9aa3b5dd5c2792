//! Giving large buffers back off the solving thread. Freeing memory that was written costs the
//! kernel time in proportion to its pages (the page tables are torn down, the pages returned):
//! the stiffness route's factor at n = 10⁷ elements (about 400 MB) took 43–55 ms to drop, most
//! of what a cancelled `dual` or enumeration solve spent between hearing the cancel and
//! returning (`cargo bench --bench cancel -- n=1e7`), and `dual-inverse`'s dense matrices at
//! N = 4000 (128 MB each) 35–57 ms. [`release`] hands a buffer of at least [`BACKGROUND_BYTES`]
//! to one long-lived thread that drops it, and [`Background`] does so for a value known to be
//! large whenever it is dropped (an early return included), so the solve returns — and its
//! core goes to the next request — at once; smaller buffers, and every value when that thread
//! cannot be started, are dropped in place. The arithmetic is untouched: this only changes
//! which thread frees.

use std::any::Any;
use std::sync::OnceLock;
use std::sync::mpsc::{Sender, channel};

/// Buffers from this size up go to the releasing thread: freeing 1 MiB costs about 0.1 ms,
/// sending it a few microseconds.
pub const BACKGROUND_BYTES: usize = 1 << 20;

type Garbage = Box<dyn Any + Send>;

/// The releasing thread's inbox, started on first use; `None` when it could not be started.
fn releaser() -> Option<&'static Sender<Garbage>> {
    static INBOX: OnceLock<Option<Sender<Garbage>>> = OnceLock::new();
    INBOX
        .get_or_init(|| {
            let (send, receive) = channel::<Garbage>();
            std::thread::Builder::new()
                .name("beamfric-release".into())
                .spawn(move || {
                    // Each message is dropped as it is received: that is the whole job.
                    for garbage in receive {
                        drop(garbage);
                    }
                })
                .ok()
                .map(|_| send)
        })
        .as_ref()
}

/// Drops `value` on the releasing thread, or here if there is none.
fn drop_in_background<T: Send + 'static>(value: T) {
    if let Some(inbox) = releaser() {
        // A send fails only if the thread is gone; the value then comes back and drops here.
        let _ = inbox.send(Box::new(value));
    }
}

/// Drops `buffer`, on the releasing thread when it is large (see the module doc).
pub fn release<T: Send + 'static>(buffer: Vec<T>) {
    if buffer.capacity() * std::mem::size_of::<T>() >= BACKGROUND_BYTES {
        drop_in_background(buffer);
    }
}

/// A value known to be large (a dense N×N matrix) that is freed on the releasing thread when
/// dropped, wherever that happens: at the end of its scope or on an early return with `?`.
pub struct Background<T: Send + 'static>(Option<T>);

impl<T: Send + 'static> Background<T> {
    pub fn new(value: T) -> Background<T> {
        Background(Some(value))
    }

    /// The value, to be dropped by its new owner.
    pub fn into_inner(mut self) -> T {
        self.0
            .take()
            .expect("a Background holds its value until dropped")
    }
}

impl<T: Send + 'static> std::ops::Deref for Background<T> {
    type Target = T;
    fn deref(&self) -> &T {
        self.0
            .as_ref()
            .expect("a Background holds its value until dropped")
    }
}

impl<T: Send + 'static> std::ops::DerefMut for Background<T> {
    fn deref_mut(&mut self) -> &mut T {
        self.0
            .as_mut()
            .expect("a Background holds its value until dropped")
    }
}

impl<T: Send + 'static> Drop for Background<T> {
    fn drop(&mut self) {
        if let Some(value) = self.0.take() {
            drop_in_background(value);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::Arc;
    use std::time::{Duration, Instant};

    /// A large buffer is freed (its last `Arc` dropped) by the releasing thread, soon.
    #[test]
    fn a_large_buffer_is_freed_by_the_releasing_thread() {
        let marker = Arc::new(());
        let mut buffer = vec![None; BACKGROUND_BYTES / std::mem::size_of::<Option<Arc<()>>>() + 1];
        buffer[0] = Some(Arc::clone(&marker));
        release(buffer);
        let deadline = Instant::now() + Duration::from_secs(30);
        while Arc::strong_count(&marker) > 1 {
            assert!(
                Instant::now() < deadline,
                "the large buffer was never freed"
            );
            std::thread::yield_now();
        }
    }

    /// A value in a `Background` is freed by the releasing thread when dropped, and given back
    /// whole by `into_inner`.
    #[test]
    fn a_background_value_is_freed_there_or_given_back() {
        let marker = Arc::new(());
        let kept = Background::new(Arc::clone(&marker));
        let back = Background::new(Arc::clone(&marker)).into_inner();
        assert_eq!(Arc::strong_count(&marker), 3);
        drop(back);
        assert_eq!(**kept, ());
        drop(kept);
        let deadline = Instant::now() + Duration::from_secs(30);
        while Arc::strong_count(&marker) > 1 {
            assert!(Instant::now() < deadline, "the value was never freed");
            std::thread::yield_now();
        }
    }

    /// A small buffer is dropped at once, in place.
    #[test]
    fn a_small_buffer_is_dropped_in_place() {
        let marker = Arc::new(());
        release(vec![Arc::clone(&marker)]);
        assert_eq!(Arc::strong_count(&marker), 1);
    }
}
