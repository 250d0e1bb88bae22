//! The sweep's progress display: indicatif's bar under the `cli` feature; without it (a
//! library built with `default-features = false`) one line per finished cell on stderr, so
//! that long work still shows where it is without compiling indicatif.

/// Progress over a known number of cells; hidden when not asked for.
pub(crate) struct Progress {
    #[cfg(feature = "cli")]
    bar: indicatif::ProgressBar,
    #[cfg(not(feature = "cli"))]
    plain: Option<Plain>,
}

#[cfg(not(feature = "cli"))]
struct Plain {
    done: u64,
    len: u64,
    message: String,
}

impl Progress {
    /// A display for `len` cells, shown when `show`.
    pub(crate) fn new(len: u64, show: bool) -> Progress {
        #[cfg(feature = "cli")]
        {
            let bar = if show {
                let b = indicatif::ProgressBar::new(len);
                b.set_style(
                    indicatif::ProgressStyle::with_template("{bar:30} {pos}/{len} cells, ETA {eta} | {msg}")
                        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
                );
                b
            } else {
                indicatif::ProgressBar::hidden()
            };
            Progress { bar }
        }
        #[cfg(not(feature = "cli"))]
        {
            Progress { plain: show.then(|| Plain { done: 0, len, message: String::new() }) }
        }
    }

    /// Sets the number of cells (the bar is shown from the start of a sweep, over the grid's
    /// cells, while the results, scenes and pipelines are read and checked; then over the
    /// cells left to measure). In the plain form, says what is being prepared on one line.
    pub(crate) fn set_len(&mut self, len: u64) {
        #[cfg(feature = "cli")]
        {
            self.bar.set_length(len);
            self.bar.set_position(0);
        }
        #[cfg(not(feature = "cli"))]
        if let Some(p) = &mut self.plain {
            p.len = len;
        }
    }

    /// Says what the sweep prepares before its first cell (the bar ticks while it does).
    pub(crate) fn preparing(&mut self, message: String) {
        #[cfg(feature = "cli")]
        {
            self.bar.enable_steady_tick(std::time::Duration::from_millis(250));
            self.bar.set_message(message);
        }
        #[cfg(not(feature = "cli"))]
        if self.plain.is_some() {
            eprintln!("{message}");
        }
    }

    /// Names the cell in flight.
    pub(crate) fn set_message(&mut self, message: String) {
        #[cfg(feature = "cli")]
        self.bar.set_message(message);
        #[cfg(not(feature = "cli"))]
        if let Some(p) = &mut self.plain {
            p.message = message;
        }
    }

    /// One more cell finished.
    pub(crate) fn inc(&mut self) {
        #[cfg(feature = "cli")]
        self.bar.inc(1);
        #[cfg(not(feature = "cli"))]
        if let Some(p) = &mut self.plain {
            p.done += 1;
            eprintln!("{}/{} cells | {}", p.done, p.len, p.message);
        }
    }

    /// Removes the bar when the sweep ends.
    pub(crate) fn finish(self) {
        #[cfg(feature = "cli")]
        self.bar.finish_and_clear();
    }
}
