//! [`ThreadedMcapLogger`]: a [`McapLogger`] on its own writer thread, fed through a bounded
//! queue and flushed every second of wall time.

use super::McapLogger;
use crate::error::Error;
use crate::Result;
use sea_loop::{ContactCheckEvent, Impact, OwnedSample, RunEnd, Sample};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Samples queued for the writer thread before [`ThreadedMcapLogger::log`] waits.
const QUEUE_SAMPLES: usize = 4096;

/// Wall time between chunk flushes of the writer thread: a killed process loses at most about
/// this much of its log (the chunks before are complete on disk and recoverable).
const FLUSH_INTERVAL: Duration = Duration::from_secs(1);

/// A [`McapLogger`] on its own thread: [`Self::log`] copies the sample into a bounded queue
/// and returns, while link kinematics, JSON, LZ4 and file writes run beside the simulation
/// (they cost about a fifth of a closed-loop tick). The file is finished by
/// [`Self::finish`], or when this is dropped, so an interrupted run still leaves a readable
/// log; a writer error is returned by the next `log` or by `finish`.
pub struct ThreadedMcapLogger {
    path: PathBuf,
    sender: Option<std::sync::mpsc::SyncSender<Queued>>,
    writer: Option<std::thread::JoinHandle<Result<()>>>,
}

/// What the writer thread of a [`ThreadedMcapLogger`] is given.
// Nearly every item is a sample: boxing it would only add an allocation per sample.
#[allow(clippy::large_enum_variant)]
enum Queued {
    /// A sample to log.
    Sample(OwnedSample),
    /// An impact.
    Impact(Impact),
    /// A change of a foot's contact check.
    ContactCheck(ContactCheckEvent),
    /// The walk as the controller changed it.
    Walking(Box<sea_ctrl::walking::Gait>),
    /// How the run ended.
    End(RunEnd),
}

impl ThreadedMcapLogger {
    /// Moves `logger` to a writer thread.
    pub fn spawn(logger: McapLogger) -> Self {
        let path = logger.path().to_path_buf();
        let (sender, receiver) = std::sync::mpsc::sync_channel::<Queued>(QUEUE_SAMPLES);
        let writer = std::thread::spawn(move || {
            let mut logger = logger;
            let mut last_flush = Instant::now();
            let mut last_time = 0.0;
            for queued in receiver {
                match queued {
                    Queued::Sample(sample) => {
                        let sample = sample.sample();
                        last_time = sample.time_s;
                        logger.log(&sample)?;
                    }
                    Queued::Impact(impact) => logger.impact(&impact)?,
                    Queued::ContactCheck(event) => logger.contact_check(&event)?,
                    Queued::Walking(gait) => logger.set_gait(*gait),
                    Queued::End(end) => logger.end(&end, last_time)?,
                }
                if last_flush.elapsed() >= FLUSH_INTERVAL {
                    logger.flush()?;
                    last_flush = Instant::now();
                }
            }
            logger.finish()
        });
        Self {
            path,
            sender: Some(sender),
            writer: Some(writer),
        }
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Queues a sample (waits only when the writer is `QUEUE_SAMPLES` behind).
    pub fn log(&mut self, sample: &Sample<'_>) -> Result<()> {
        self.send(Queued::Sample(sample.to_owned()))
    }

    /// Queues an impact ([`McapLogger::impact`]).
    pub fn impact(&mut self, impact: &Impact) -> Result<()> {
        self.send(Queued::Impact(impact.clone()))
    }

    /// Queues the walk as the controller changed it ([`McapLogger::set_gait`]).
    pub fn set_gait(&mut self, gait: &sea_ctrl::walking::Gait) -> Result<()> {
        self.send(Queued::Walking(Box::new(gait.clone())))
    }

    /// Queues a change of a foot's contact check ([`McapLogger::contact_check`]).
    pub fn contact_check(&mut self, event: &ContactCheckEvent) -> Result<()> {
        self.send(Queued::ContactCheck(event.clone()))
    }

    /// Queues how the run ended ([`McapLogger::end`], at the last sample's time).
    pub fn end(&mut self, end: &RunEnd) -> Result<()> {
        self.send(Queued::End(end.clone()))
    }

    /// Queues `item`, or reports the writer's error when it stopped.
    fn send(&mut self, item: Queued) -> Result<()> {
        let queued = match &self.sender {
            Some(sender) => sender.send(item).is_ok(),
            None => false,
        };
        if queued {
            Ok(())
        } else {
            // The writer stopped on an error: report it.
            self.join()
        }
    }

    /// Writes the queued samples, the summary and the index, and closes the file.
    pub fn finish(mut self) -> Result<()> {
        self.join()
    }

    /// Ends the writer and returns its outcome; once joined, every call is an error (the
    /// writer's own error was reported by the first).
    fn join(&mut self) -> Result<()> {
        self.sender = None; // ends the writer's loop
        match self.writer.take() {
            Some(handle) => handle.join().unwrap_or_else(|_| {
                Err(Error::Log(format!(
                    "the writer thread of {} panicked",
                    self.path.display()
                )))
            }),
            None => Err(Error::Log(format!(
                "{}: the writer already stopped",
                self.path.display()
            ))),
        }
    }
}

impl Drop for ThreadedMcapLogger {
    fn drop(&mut self) {
        let _ = self.join();
    }
}
