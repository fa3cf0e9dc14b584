//! Soak runs: the system runs for a set time (or number of cycles) while the
//! supervisor samples every process once a second (resident memory, open
//! file descriptors) and the run's shared-memory files, optionally with
//! faults injected ([`crate::chaos`]). At the end it writes `soak.csv`,
//! `soak.svg` and `soak.json`, and a verdict line.
//!
//! Memory growth is measured after a warm-up (the first fifth of each
//! process's life, at least 15 s: a restarted process warms up again) and
//! outside each fault and the five seconds after it: for each process, the sum of
//! its steps from one sample to the next in those stretches, against the mean
//! of its first five samples after the warm-up (descriptors: the same sum);
//! the largest over processes is reported.

use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use plotters::prelude::*;
use serde::Serialize;

use crate::chaos::{Chaos, ChaosRecord, SoakClock};
use crate::json_error;
use learnpnp::experiment::plot::{FONT, PLOT_SIZE, colour};
use learnpnp::experiment::result_dir::ResultWriter;
use learnpnp_system::ipc::namespace::SHM_DIR;
use learnpnp_system::latency::plot::PlotFailure;
pub use learnpnp_system::multiprocess::supervisor::SampleLogError;
use learnpnp_system::multiprocess::supervisor::{Fault, Request, RunObserver, RunRecord, RunView, SupervisorError};

/// Share of each process's life treated as warm-up.
const WARM_UP_SHARE: f64 = 0.2;

/// The shortest warm-up, in seconds: a run opens some shared-memory
/// connections only when its episode loop begins, after the floor measurement
/// (five seconds in real time).
const WARM_UP_MIN_SECONDS: f64 = 15.0;

/// Samples averaged for the base of the post-warm-up window (and the fewest
/// it needs at each end).
const ENDS: usize = 5;

/// Seconds after a fault (injected, or a process's exit) is over during
/// which growth is not counted (nor while it lasts): a first restart pages in
/// code not run before and makes the survivors connect to the new process,
/// and CPU load runs threads in the supervisor, once.
const FAULT_SETTLE_SECONDS: f64 = 5.0;

/// The verdict's memory-growth limit, in percent.
pub(crate) const RSS_GROWTH_LIMIT: f64 = 1.0;

/// When a soak ends.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SoakLimits {
    /// After this long.
    pub duration: Option<Duration>,
    /// After this many cycles (over every run).
    pub cycles: Option<u64>,
}

/// One process at one second of the soak.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct Sample {
    /// Seconds since the soak began.
    pub seconds: f64,
    /// `supervisor`, `simulator`, `keeper 1`, ...
    pub process: String,
    /// Its process id.
    pub pid: u32,
    /// Resident memory, KiB.
    pub(crate) rss_kib: u64,
    /// Its anonymous part (heap and stacks: what a leak grows), KiB; the
    /// rest is the program's own pages and mapped shared memory.
    pub(crate) anon_kib: u64,
    /// Open file descriptors.
    pub(crate) open_fds: u64,
    /// Files of the run's namespace in `/dev/shm`.
    pub(crate) shm_files: u64,
    /// Their size, bytes.
    pub(crate) shm_bytes: u64,
}

/// `soak.json`.
#[derive(Debug, Clone, Serialize)]
pub struct SoakReport {
    /// PASS or FAIL, and why.
    pub verdict: String,
    /// The soak passed.
    pub passed: bool,
    /// Seconds the soak ran.
    pub seconds: f64,
    /// Cycles played.
    pub cycles: u64,
    /// Learning episodes completed.
    pub episodes: u64,
    /// Largest resident-memory growth of a process after warm-up, percent.
    pub(crate) rss_growth_percent: f64,
    /// The process it was.
    pub(crate) rss_growth_process: String,
    /// Largest growth of a process's open file descriptors after warm-up,
    /// counting a descriptor when two samples in a row find it open (a file
    /// held while it is written, as a checkpoint writer does, is no leak).
    pub(crate) fd_growth: i64,
    /// Processes restarted.
    pub restarts: u32,
    /// Real time: commands that missed their cycle.
    pub missed_deadlines: u64,
    /// Every restarted agent resumed with the values checkpointed before it.
    pub(crate) values_survived: bool,
    /// Faults: injected ones with what happened, and those the supervisor handled.
    pub faults: Vec<FaultReport>,
    /// The run failed (a process the run could not do without was lost).
    pub(crate) failure: Option<String>,
    /// Files of the runs' namespaces left after cleanup.
    pub(crate) leftover_shm_files: usize,
}

/// A fault in the soak's report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FaultReport {
    /// What happened.
    pub kind: String,
    /// Seconds since the soak (injected faults) or the run (others) began.
    pub time: f64,
    /// What came of it.
    pub outcome: String,
    /// The system survived it (no loss, the run went on).
    pub survived: bool,
}

/// The soak observer.
#[derive(Debug)]
pub struct Soak {
    limits: SoakLimits,
    started: Instant,
    next_sample: f64,
    /// Samples go straight to `soak.csv` (kept in memory, they would be the
    /// supervisor's growth); it is read back at the end.
    log: Option<SampleLog>,
    chaos: Option<Chaos>,
    cycles_done: u64,
    last_run: Option<usize>,
    last_cycles: u64,
    report: Option<SoakReport>,
}

impl Soak {
    /// A soak within `limits`, with `chaos` injecting faults if given.
    pub fn new(limits: SoakLimits, chaos: Option<Chaos>) -> Self {
        Soak {
            limits,
            started: Instant::now(),
            next_sample: 0.0,
            log: None,
            chaos,
            cycles_done: 0,
            last_run: None,
            last_cycles: 0,
            report: None,
        }
    }

    /// The report, once the soak has finished.
    pub fn report(&self) -> Option<&SoakReport> {
        self.report.as_ref()
    }

    fn sample(&mut self, seconds: f64, view: &RunView<'_>) {
        let Some(log) = &mut self.log else {
            return;
        };
        let (shm_files, shm_bytes) = shm_usage(view.namespace.prefix());
        let me = ("supervisor".to_string(), std::process::id());
        let processes = std::iter::once(me).chain(view.processes.iter().map(|(role, pid)| (role.to_string(), *pid)));
        for (process, pid) in processes {
            if let (Some(rss_kib), Some(open_fds)) = (rss_kib(pid), open_fds(pid)) {
                log.write(&Sample {
                    seconds,
                    process,
                    pid,
                    rss_kib,
                    anon_kib: anon_kib(pid).unwrap_or(0),
                    open_fds,
                    shm_files,
                    shm_bytes,
                });
            }
        }
        log.flush();
    }
}

/// `soak.csv`, written as the samples are taken.
#[derive(Debug)]
struct SampleLog {
    path: PathBuf,
    file: BufWriter<File>,
    /// The first write that failed (reported when the soak ends).
    error: Option<std::io::Error>,
}

/// The header of `soak.csv`.
const CSV_HEADER: &str = "seconds,process,pid,rss_kib,anon_kib,open_fds,shm_files,shm_bytes";

impl SampleLog {
    fn create(path: PathBuf) -> std::io::Result<Self> {
        let mut file = BufWriter::new(File::create(&path)?);
        writeln!(file, "{CSV_HEADER}")?;
        Ok(SampleLog {
            path,
            file,
            error: None,
        })
    }

    fn write(&mut self, s: &Sample) {
        let written = writeln!(
            self.file,
            "{:.1},{},{},{},{},{},{},{}",
            s.seconds, s.process, s.pid, s.rss_kib, s.anon_kib, s.open_fds, s.shm_files, s.shm_bytes
        );
        if let Err(e) = written {
            self.error.get_or_insert(e);
        }
    }

    fn flush(&mut self) {
        if let Err(e) = self.file.flush() {
            self.error.get_or_insert(e);
        }
    }

    /// Every sample written, read back.
    fn finish(mut self) -> Result<Vec<Sample>, SampleLogError> {
        self.flush();
        let path = self.path;
        let io = |source| SampleLogError::Io {
            path: path.clone(),
            source,
        };
        if let Some(e) = self.error {
            return Err(io(e));
        }
        let file = File::open(&path).map_err(io)?;
        let mut samples = Vec::new();
        for line in BufReader::new(file).lines().skip(1) {
            let line = line.map_err(io)?;
            let sample = parse_sample(&line).ok_or_else(|| SampleLogError::Unreadable {
                path: path.clone(),
                line: line.clone(),
            })?;
            samples.push(sample);
        }
        Ok(samples)
    }
}

/// One line of `soak.csv`.
fn parse_sample(line: &str) -> Option<Sample> {
    let f: Vec<&str> = line.split(',').collect();
    let [seconds, process, pid, rss_kib, anon_kib, open_fds, shm_files, shm_bytes] = f.as_slice() else {
        return None;
    };
    Some(Sample {
        seconds: seconds.parse().ok()?,
        process: process.to_string(),
        pid: pid.parse().ok()?,
        rss_kib: rss_kib.parse().ok()?,
        anon_kib: anon_kib.parse().ok()?,
        open_fds: open_fds.parse().ok()?,
        shm_files: shm_files.parse().ok()?,
        shm_bytes: shm_bytes.parse().ok()?,
    })
}

impl RunObserver for Soak {
    fn observe(&mut self, view: &RunView<'_>) -> Vec<Request> {
        let seconds = self.started.elapsed().as_secs_f64();
        if seconds >= self.next_sample {
            self.sample(seconds, view);
            self.next_sample = seconds.floor() + 1.0;
        }
        let cycles = view.simulator.map_or(0, |p| p.cycles);
        if self.last_run != Some(view.run) {
            self.cycles_done += self.last_cycles;
            self.last_run = Some(view.run);
        }
        self.last_cycles = cycles;
        let now = SoakClock {
            seconds,
            cycles: self.cycles_done + cycles,
        };
        let mut requests = match &mut self.chaos {
            Some(chaos) => chaos.tick(now, view),
            None => Vec::new(),
        };
        let timed_out = self.limits.duration.is_some_and(|d| seconds >= d.as_secs_f64());
        let cycled = self.limits.cycles.is_some_and(|c| self.cycles_done + cycles >= c);
        if timed_out || cycled {
            requests.push(Request::Stop);
        }
        requests
    }

    fn start(&mut self, files: &mut ResultWriter<'_>) -> Result<(), SupervisorError> {
        let path = files.path_for("soak.csv")?;
        let log = SampleLog::create(path.clone()).map_err(|source| SupervisorError::Io { path, source })?;
        self.log = Some(log);
        Ok(())
    }

    fn finish(&mut self, files: &mut ResultWriter<'_>, records: &[RunRecord]) -> Result<(), SupervisorError> {
        let seconds = self.started.elapsed().as_secs_f64();
        let injected: Vec<ChaosRecord> = self.chaos.as_mut().map(|c| c.finish(records)).unwrap_or_default();
        let samples = match self.log.take() {
            Some(log) => log.finish()?,
            None => Vec::new(),
        };
        let report = analyse(&samples, &injected, records, seconds);
        files.add_text("soak.svg", &plot(&samples)?)?;
        let json = serde_json::to_string_pretty(&report).map_err(json_error("soak.json"))?;
        files.add_text("soak.json", &json)?;
        self.report = Some(report);
        Ok(())
    }
}

/// Resident memory of `pid`, KiB.
fn rss_kib(pid: u32) -> Option<u64> {
    let statm = std::fs::read_to_string(format!("/proc/{pid}/statm")).ok()?;
    let pages: u64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    // SAFETY: sysconf only reads a system constant.
    let page = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    Some(pages * u64::try_from(page).ok()? / 1024)
}

/// Anonymous resident memory of `pid` (`RssAnon` of its status), KiB.
fn anon_kib(pid: u32) -> Option<u64> {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("RssAnon:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Open file descriptors of `pid`.
fn open_fds(pid: u32) -> Option<u64> {
    Some(std::fs::read_dir(format!("/proc/{pid}/fd")).ok()?.count() as u64)
}

/// Files of `prefix` in `/dev/shm` and their total size.
fn shm_usage(prefix: &str) -> (u64, u64) {
    let Ok(entries) = std::fs::read_dir(SHM_DIR) else {
        return (0, 0);
    };
    entries
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with(prefix))
        .fold((0, 0), |(n, bytes), e| {
            (n + 1, bytes + e.metadata().map_or(0, |m| m.len()))
        })
}

/// The mean of `values`.
fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

/// Growth of each process incarnation after its warm-up: (process, rss %,
/// fds). Descriptors count when two samples in a row find them open: each
/// sample's count is the lesser of it and the next one's, the last sample
/// having no next is left out.
fn growth(samples: &[Sample], faults: &[(f64, f64)]) -> Vec<(String, f64, i64)> {
    let quiet = |t: f64| {
        !faults
            .iter()
            .any(|&(began, ended)| (began..ended + FAULT_SETTLE_SECONDS).contains(&t))
    };
    let mut incarnations: Vec<(String, u32)> = samples.iter().map(|s| (s.process.clone(), s.pid)).collect();
    incarnations.sort();
    incarnations.dedup();
    incarnations
        .into_iter()
        .filter_map(|(process, pid)| {
            let life: Vec<&Sample> = samples
                .iter()
                .filter(|s| s.pid == pid && s.process == process)
                .collect();
            let (born, died) = (life.first()?.seconds, life.last()?.seconds);
            let warm_up = born + (WARM_UP_SHARE * (died - born)).max(WARM_UP_MIN_SECONDS);
            let after: Vec<&Sample> = life.into_iter().filter(|s| s.seconds >= warm_up).collect();
            if after.len() < 2 * ENDS {
                return None;
            }
            let base = mean(&after[..ENDS].iter().map(|s| s.rss_kib as f64).collect::<Vec<_>>());
            let rss: f64 = after
                .windows(2)
                .filter(|w| quiet(w[0].seconds) && quiet(w[1].seconds))
                .map(|w| w[1].rss_kib as f64 - w[0].rss_kib as f64)
                .sum();
            let held: Vec<(f64, i64)> = after
                .windows(2)
                .map(|w| (w[0].seconds, w[0].open_fds.min(w[1].open_fds) as i64))
                .collect();
            let fds: i64 = held
                .windows(2)
                .filter(|w| quiet(w[0].0) && quiet(w[1].0))
                .map(|w| w[1].1 - w[0].1)
                .sum();
            Some((format!("{process} (pid {pid})"), 100.0 * rss / base.max(1.0), fds))
        })
        .collect()
}

/// The soak's report from its samples, the faults injected, and the runs.
fn analyse(samples: &[Sample], injected: &[ChaosRecord], records: &[RunRecord], seconds: f64) -> SoakReport {
    let faults: Vec<(f64, f64)> = injected
        .iter()
        .map(|f| (f.time, f.ended))
        .chain(
            records
                .iter()
                .flat_map(|r| r.faults.iter().map(|f| (f.seconds, f.seconds))),
        )
        .collect();
    let growth = growth(samples, &faults);
    let (rss_growth_process, rss_growth_percent) = growth
        .iter()
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map_or((String::new(), 0.0), |(p, g, _)| (p.clone(), *g));
    let fd_growth = growth.iter().map(|(_, _, f)| *f).max().unwrap_or(0);
    let failure = records.iter().find_map(|r| r.failure.clone());
    let values_survived = records.iter().flat_map(|r| &r.resumes).all(|c| c.survived);
    let leftover_shm_files = records.iter().map(|r| r.leftover_files).sum();
    let mut faults: Vec<FaultReport> = injected
        .iter()
        .map(|c| FaultReport {
            kind: c.kind.clone(),
            time: c.time,
            outcome: c.outcome.clone(),
            survived: c.survived,
        })
        .collect();
    faults.extend(
        records
            .iter()
            .flat_map(|r| &r.faults)
            .filter(|f| !f.kind.starts_with("stop requested"))
            .map(|f: &Fault| FaultReport {
                kind: format!("run {}: {}", f.run, f.kind),
                time: f.seconds,
                outcome: f.outcome.clone(),
                survived: failure.is_none(),
            }),
    );
    let mut problems = Vec::new();
    if growth.is_empty() {
        problems.push(format!(
            "too short to judge memory: no process lived {} samples past its warm-up (at least {WARM_UP_MIN_SECONDS} s)",
            2 * ENDS
        ));
    }
    if rss_growth_percent >= RSS_GROWTH_LIMIT {
        problems.push(format!(
            "resident memory of {rss_growth_process} grew {rss_growth_percent:.2}% after warm-up (limit {RSS_GROWTH_LIMIT}%)"
        ));
    }
    if fd_growth > 0 {
        problems.push(format!("{fd_growth} more open file descriptors after warm-up"));
    }
    if let Some(f) = &failure {
        problems.push(format!("the run failed: {f}"));
    }
    if !values_survived {
        problems.push("a restarted agent did not resume with its checkpointed values".into());
    }
    if let Some(f) = faults.iter().find(|f| !f.survived) {
        problems.push(format!("not survived: {} ({})", f.kind, f.outcome));
    }
    if leftover_shm_files > 0 {
        problems.push(format!("{leftover_shm_files} files left in /dev/shm"));
    }
    let restarts = records.iter().map(|r| r.restarts).sum();
    let missed_deadlines = records.iter().map(|r| r.sim.totals.missed_deadlines).sum();
    let passed = problems.is_empty();
    let verdict = if passed {
        format!(
            "PASS: {seconds:.0} s, memory growth {rss_growth_percent:.2}% (< {RSS_GROWTH_LIMIT}%), {} faults survived, {restarts} restarts with the values kept, {missed_deadlines} missed deadlines, nothing left in /dev/shm",
            faults.len()
        )
    } else {
        format!("FAIL: {}", problems.join("; "))
    };
    SoakReport {
        verdict,
        passed,
        seconds,
        cycles: records.iter().map(|r| r.sim.totals.cycles).sum(),
        episodes: records.iter().map(|r| r.sim.totals.learning_episodes).sum(),
        rss_growth_percent,
        rss_growth_process,
        fd_growth,
        restarts,
        missed_deadlines,
        values_survived,
        faults,
        failure,
        leftover_shm_files,
    }
}

/// Resident memory (top) and open descriptors with shared-memory files
/// (bottom) of every process over the soak.
fn plot(samples: &[Sample]) -> Result<String, PlotFailure> {
    let mut processes: Vec<String> = samples.iter().map(|s| s.process.clone()).collect();
    processes.sort();
    processes.dedup();
    let t_max = samples.iter().map(|s| s.seconds).fold(1.0, f64::max);
    let rss_max = samples.iter().map(|s| s.rss_kib as f64 / 1024.0).fold(1.0, f64::max) * 1.1;
    let count_max = samples
        .iter()
        .map(|s| s.open_fds.max(s.shm_files) as f64)
        .fold(1.0, f64::max)
        * 1.1;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (PLOT_SIZE.0, PLOT_SIZE.1 + 240)).into_drawing_area();
        let draw = || -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
            root.fill(&WHITE)?;
            let (top, bottom) = root.split_vertically(PLOT_SIZE.1 / 2 + 120);
            let mut rss = ChartBuilder::on(&top)
                .caption("resident memory per process", (FONT, 18))
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(64)
                .build_cartesian_2d(0.0..t_max, 0.0..rss_max)?;
            rss.configure_mesh()
                .x_desc("seconds")
                .y_desc("MiB")
                .label_style((FONT, 12))
                .draw()?;
            let mut counts = ChartBuilder::on(&bottom)
                .caption(
                    "open file descriptors per process; shared-memory files of the run",
                    (FONT, 18),
                )
                .margin(12)
                .x_label_area_size(36)
                .y_label_area_size(64)
                .build_cartesian_2d(0.0..t_max, 0.0..count_max)?;
            counts
                .configure_mesh()
                .x_desc("seconds")
                .y_desc("count")
                .label_style((FONT, 12))
                .draw()?;
            for (i, process) in processes.iter().enumerate() {
                let style = colour(i).stroke_width(2);
                let mine: Vec<&Sample> = samples.iter().filter(|s| &s.process == process).collect();
                rss.draw_series(LineSeries::new(
                    mine.iter().map(|s| (s.seconds, s.rss_kib as f64 / 1024.0)),
                    style,
                ))?
                .label(process.as_str())
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], style));
                counts.draw_series(LineSeries::new(
                    mine.iter().map(|s| (s.seconds, s.open_fds as f64)),
                    style,
                ))?;
            }
            let shm = colour(processes.len()).stroke_width(2);
            let mut by_time: Vec<(f64, f64)> = samples.iter().map(|s| (s.seconds, s.shm_files as f64)).collect();
            by_time.dedup_by(|a, b| a.0 == b.0);
            counts
                .draw_series(LineSeries::new(by_time, shm))?
                .label("shared-memory files")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], shm));
            rss.configure_series_labels()
                .position(SeriesLabelPosition::LowerRight)
                .label_font((FONT, 12))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.4))
                .draw()?;
            counts
                .configure_series_labels()
                .position(SeriesLabelPosition::LowerRight)
                .label_font((FONT, 12))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.4))
                .draw()?;
            root.present()
        };
        draw().map_err(|e| PlotFailure::new("the soak plot", e))?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn samples(process: &str, pid: u32, rss: impl Fn(usize) -> u64) -> Vec<Sample> {
        (0..30)
            .map(|i| Sample {
                seconds: i as f64,
                process: process.into(),
                pid,
                rss_kib: rss(i),
                anon_kib: rss(i) / 4,
                open_fds: 12,
                shm_files: 40,
                shm_bytes: 1 << 20,
            })
            .collect()
    }

    #[test]
    fn growth_is_measured_after_the_warm_up() {
        // Flat after a warm-up climb: no growth.
        let flat = samples("keeper 1", 7, |i| if i < 6 { 1000 + 100 * i as u64 } else { 2000 });
        let g = growth(&flat, &[]);
        assert_eq!(g.len(), 1);
        assert!(g[0].1.abs() < 1e-9, "{g:?}");
        // A steady leak of 10 KiB a second on about 2170 KiB, over the
        // 14 s after a 15 s warm-up.
        let leak = samples("simulator", 8, |i| 2000 + 10 * i as u64);
        let g = growth(&leak, &[]);
        assert!((6.0..7.0).contains(&g[0].1), "{g:?}");
        // A step at a fault is not counted; the steady leak still is.
        let mut step = samples("supervisor", 1, |_| 2000);
        step[20..].iter_mut().for_each(|s| s.rss_kib += 100);
        assert!(growth(&step, &[(19.5, 19.5)])[0].1.abs() < 1e-9);
        assert!(growth(&step, &[])[0].1 > 4.0);
        assert!(growth(&leak, &[(19.5, 19.5)])[0].1 > 3.0);
        // A fault that lasts: its whole span is left out.
        let mut late = samples("supervisor", 1, |_| 2000);
        late[27..].iter_mut().for_each(|s| s.rss_kib += 100);
        assert!(growth(&late, &[(16.5, 26.5)])[0].1.abs() < 1e-9);
    }

    #[test]
    fn samples_read_back_as_written() {
        let dir = std::env::temp_dir().join(format!("learnpnp-soak-log-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut log = SampleLog::create(dir.join("soak.csv")).unwrap();
        let written = samples("keeper 3", 11, |i| 4000 + i as u64);
        written.iter().for_each(|s| log.write(s));
        let read = log.finish().unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
        assert_eq!(read, written);
        assert!(parse_sample("1.0,keeper 1,5,10,3,4,NaN,8").is_none());
    }

    #[test]
    fn descriptors_count_when_they_stay_open() {
        // A peer's restart: one sample with more descriptors.
        let mut blip = samples("keeper 2", 9, |_| 2000);
        blip[27].open_fds += 6;
        assert_eq!(growth(&blip, &[])[0].2, 0);
        // A file open while it is written, caught by the last sample, or by
        // the sample before a fault's span: no leak either.
        let mut last = samples("keeper 2", 9, |_| 2000);
        last[29].open_fds += 1;
        assert_eq!(growth(&last, &[])[0].2, 0);
        let mut before_fault = samples("keeper 2", 9, |_| 2000);
        before_fault[20].open_fds += 1;
        assert_eq!(growth(&before_fault, &[(20.5, 22.0)])[0].2, 0);
        // One more descriptor every second: a leak (the last second's is not
        // yet confirmed by a second sample).
        let mut leak = samples("keeper 2", 9, |_| 2000);
        for (i, s) in leak.iter_mut().enumerate() {
            s.open_fds += i as u64;
        }
        assert_eq!(growth(&leak, &[])[0].2, 13);
        // One that stays open from some point on: counted.
        let mut stays = samples("keeper 2", 9, |_| 2000);
        stays[25..].iter_mut().for_each(|s| s.open_fds += 1);
        assert_eq!(growth(&stays, &[])[0].2, 1);
    }

    #[test]
    fn a_soak_without_faults_passes_on_flat_memory() {
        let s = samples("keeper 1", 7, |_| 2000);
        let report = analyse(&s, &[], &[], 30.0);
        assert!(report.passed, "{}", report.verdict);
        assert!(report.verdict.starts_with("PASS"));
        let leak = samples("keeper 1", 7, |i| 2000 + 10 * i as u64);
        let report = analyse(&leak, &[], &[], 30.0);
        assert!(!report.passed && report.verdict.contains("grew"), "{}", report.verdict);
        assert!(plot(&leak).unwrap().contains("resident memory per process"));
        let short: Vec<Sample> = s.into_iter().filter(|x| x.seconds < 20.0).collect();
        let report = analyse(&short, &[], &[], 20.0);
        assert!(
            !report.passed && report.verdict.contains("too short"),
            "{}",
            report.verdict
        );
    }
}
