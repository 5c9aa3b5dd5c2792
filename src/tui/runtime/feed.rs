//! What feeds an explorer's event loop from outside its thread — the bytes a client types, its
//! window changes, a presenter's states, a hang-up — and the two things the loop hears ahead of
//! its queue: a hang-up (a closed connection ends its session at once, whatever is queued
//! behind it) and the newest window size (a flood of window changes costs one resize per frame,
//! and queues nothing).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use std::sync::mpsc::{Receiver, Sender, channel};

use crate::tui::state::Exploration;
use crate::tui::state::follow::ClassNews;

use crate::tui::jobs::solve::Solved;
use crate::tui::jobs::sweeps::SweepResult;

/// What wakes the loop.
pub enum Event {
    /// Bytes from the terminal.
    Bytes(Vec<u8>),
    /// A remote terminal's window changed: the newest size is in the feed's signals.
    Resize,
    /// The terminal's input is gone.
    Hangup,
    /// A signal (the local terminal only).
    Signal(i32),
    /// The solve worker's output: a solve, or the message of its failure.
    Solved(Box<Result<Solved, String>>),
    /// The sweep worker's output.
    Swept(SweepResult),
    /// The presenter's new state (follow mode).
    Follow(Arc<Exploration>),
    /// News of the class (follow mode): the presenter left, the class ended.
    Class(ClassNews),
    /// Nothing but a new frame (e.g. the number of followers changed).
    Redraw,
    /// A note for the user from outside the explorer (the recording cannot be written).
    Notice(String),
}

/// Largest terminal accepted, in cells: 500 columns × 200 rows, more than a 4K screen shows at
/// an 8 × 16-pixel font (480 × 135). A hostile client could ask for 65535 × 65535.
pub const MAX_SIZE: (u16, u16) = (500, 200);

/// The size assumed when a client reports none (zero: RFC 4254 says to ignore it).
pub const UNKNOWN_SIZE: (u16, u16) = (80, 24);

/// A size the client reported, within `1..=`[`MAX_SIZE`]; a zero is [`UNKNOWN_SIZE`].
pub fn clamp_size(width: u32, height: u32) -> (u16, u16) {
    let clamp = |v: u32, max: u16, unknown: u16| match v {
        0 => unknown,
        v => v.min(u32::from(max)) as u16,
    };
    (
        clamp(width, MAX_SIZE.0, UNKNOWN_SIZE.0),
        clamp(height, MAX_SIZE.1, UNKNOWN_SIZE.1),
    )
}

/// What a feed tells its loop ahead of the queue.
#[derive(Debug, Default)]
pub struct Signals {
    hung_up: AtomicBool,
    /// The newest window size (columns << 16 | rows); 0: none reported since the last taken.
    newest_size: AtomicU32,
    /// A redraw was asked for and not yet taken: more asks queue nothing (a student toggling
    /// their unsaved work or their fork as fast as they can type cannot flood a presenter).
    redraw_pending: AtomicBool,
}

impl Signals {
    /// Has the input hung up? The loop asks before every event and every key it applies.
    pub fn hung_up(&self) -> bool {
        self.hung_up.load(Ordering::Acquire)
    }

    /// The loop is about to draw: a redraw asked for from now on wakes it again.
    pub fn take_redraw(&self) {
        self.redraw_pending.store(false, Ordering::Release);
    }

    /// The newest window size reported since the last call, if any.
    pub fn take_size(&self) -> Option<(u16, u16)> {
        match self.newest_size.swap(0, Ordering::AcqRel) {
            0 => None,
            packed => Some(((packed >> 16) as u16, (packed & 0xffff) as u16)),
        }
    }
}

/// Where an explorer's events come from: the receiver its loop reads, a sender for its own
/// workers, and the signals its feeds set.
pub struct Events {
    pub sender: Sender<Event>,
    pub receiver: Receiver<Event>,
    pub signals: Arc<Signals>,
}

/// A new channel of events, and the feed that writes into it.
pub fn events() -> (Feed, Events) {
    let (sender, receiver) = channel();
    let signals = Arc::new(Signals::default());
    let feed = Feed {
        sender: sender.clone(),
        signals: Arc::clone(&signals),
    };
    (
        feed,
        Events {
            sender,
            receiver,
            signals,
        },
    )
}

/// What the connection (or a presenter's hub) tells an explorer. Cheap to clone; telling an
/// explorer that has ended does nothing.
#[derive(Clone)]
pub struct Feed {
    sender: Sender<Event>,
    signals: Arc<Signals>,
}

impl std::fmt::Debug for Feed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Feed")
    }
}

impl Feed {
    /// A feed into the loop of `events` (the local explorer's, see [`super::local::run_local`]).
    pub fn of(events: &Events) -> Feed {
        Feed {
            sender: events.sender.clone(),
            signals: Arc::clone(&events.signals),
        }
    }

    /// Bytes the client typed.
    pub fn bytes(&self, bytes: &[u8]) {
        if !self.signals.hung_up() {
            let _ = self.sender.send(Event::Bytes(bytes.to_vec()));
        }
    }

    /// The client's window changed: only the newest size is kept, and the loop is woken once
    /// until it takes it.
    pub fn resize(&self, width: u32, height: u32) {
        let (width, height) = clamp_size(width, height);
        let packed = u32::from(width) << 16 | u32::from(height);
        if self.signals.newest_size.swap(packed, Ordering::AcqRel) == 0 {
            let _ = self.sender.send(Event::Resize);
        }
    }

    /// The presenter's new state (follow mode).
    pub fn follow(&self, exploration: Arc<Exploration>) {
        let _ = self.sender.send(Event::Follow(exploration));
    }

    /// News of the class (follow mode).
    pub fn class_news(&self, news: ClassNews) {
        let _ = self.sender.send(Event::Class(news));
    }

    /// A note for the user, shown as the explorer's message.
    pub fn notice(&self, text: String) {
        let _ = self.sender.send(Event::Notice(text));
    }

    /// Draw again (something the frame shows changed outside the explorer); one wake-up until
    /// the loop takes it, however many asks.
    pub fn redraw(&self) {
        if !self.signals.redraw_pending.swap(true, Ordering::AcqRel) {
            let _ = self.sender.send(Event::Redraw);
        }
    }

    /// The client went away: the loop ends before it applies anything more.
    pub fn hangup(&self) {
        self.signals.hung_up.store(true, Ordering::Release);
        let _ = self.sender.send(Event::Hangup);
    }

    /// Has the explorer's client gone away?
    pub fn is_hung_up(&self) -> bool {
        self.signals.hung_up()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_clamped_and_resizes_coalesce_to_the_newest() {
        assert_eq!(clamp_size(0, 0), UNKNOWN_SIZE);
        assert_eq!(clamp_size(65535, 65535), MAX_SIZE);
        assert_eq!(clamp_size(100, 30), (100, 30));
        let (feed, events) = events();
        for width in 100..200 {
            feed.resize(width, 40);
        }
        // One wake-up for the hundred changes; the size taken is the last one.
        assert_eq!(events.receiver.try_iter().count(), 1);
        assert_eq!(events.signals.take_size(), Some((199, 40)));
        assert_eq!(events.signals.take_size(), None);
        feed.resize(90, 20);
        assert_eq!(events.receiver.try_iter().count(), 1);
    }

    #[test]
    fn redraws_coalesce_until_the_loop_takes_them() {
        let (feed, events) = events();
        for _ in 0..1000 {
            feed.redraw();
        }
        assert_eq!(events.receiver.try_iter().count(), 1);
        events.signals.take_redraw();
        feed.redraw();
        feed.redraw();
        assert_eq!(events.receiver.try_iter().count(), 1);
    }

    #[test]
    fn a_hangup_is_heard_ahead_of_the_queue_and_stops_further_bytes() {
        let (feed, events) = events();
        feed.bytes(b"abc");
        assert!(!events.signals.hung_up());
        feed.hangup();
        assert!(events.signals.hung_up());
        feed.bytes(b"def");
        let queued: Vec<Event> = events.receiver.try_iter().collect();
        assert_eq!(queued.len(), 2, "the bytes before, then the hang-up");
    }
}
