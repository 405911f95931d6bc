//! Running LinuxCNC's stand-alone interpreter, `rs274 -n 0 -g` (Debian package
//! linuxcnc-uspace), on a program text: the process half of the LinuxCNC backend; its output
//! is read by [`super::linuxcnc::parse_canon`].
//!
//! Each run gets a folder of its own (`skinpath-rs274-PID-N` under the system temporary
//! folder) that is its working directory **and its `HOME`**: rs274 maps its tool data
//! through `$HOME/.tool.mmap`, opened with `O_TRUNC`, so two runs sharing a home truncate
//! each other's mapping and one dies of `SIGBUS` with its buffered standard output lost
//! (seen as about 1 in 25 runs when six run at once). A run killed by a signal is an error,
//! never an empty reading. The folder goes on every exit path; folders left by killed
//! processes are removed by the next run.
//!
//! The time limit is on work, not on the wall clock: rs274 is stopped when it has used
//! [`Rs274Options::timeout`] of processor time (user + system, read from
//! `/proc/PID/stat`), so a machine busy with other work, which stretches the wall time of a
//! run but not its processor time, does not stop a program that would finish. Only a run
//! that stays [`WALL_BACKSTOP_FACTOR`] times that long on the wall clock (rs274 blocked
//! without working) is stopped on the wall clock; where `/proc` cannot be read (not Linux)
//! the limit is the wall clock.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Prefix of the temporary folders of rs274 runs.
pub const TMP_PREFIX: &str = "skinpath-rs274-";

/// A run still going after this many times [`Rs274Options::timeout`] of wall time is
/// stopped whatever processor time it used: rs274 blocked without working (it reads no
/// input, so this is a safeguard, not an expected path). Large enough that a process
/// given a thirtieth of a processor on a busy machine still reaches its processor-time
/// limit first.
pub const WALL_BACKSTOP_FACTOR: u32 = 30;

/// Clock ticks per second of the `utime` and `stime` fields of `/proc/PID/stat`
/// (proc(5): "measured in clock ticks (divide by sysconf(_SC_CLK_TCK))"): Linux's `USER_HZ`,
/// fixed at 100 on every architecture LinuxCNC is packaged for (amd64, arm64, armhf, i386).
const USER_HZ: f64 = 100.0;

/// How to run rs274.
#[derive(Clone, Debug)]
#[non_exhaustive]
pub struct Rs274Options {
    /// rs274 is killed when it has used this much processor time (user + system; the wall
    /// clock where `/proc` cannot be read): a runaway `while` loop never ends.
    pub timeout: Duration,
    /// rs274 is killed when its standard output passes this many bytes (a runaway loop that
    /// moves would fill the disk).
    pub max_output: u64,
    /// Folders whose `.ngc` files are copied next to the program, where rs274 looks for
    /// called subroutines. Files of earlier folders win.
    pub sub_dirs: Vec<PathBuf>,
    /// A LinuxCNC tool table (`-t`); rs274's own sample table otherwise.
    pub tool_table: Option<PathBuf>,
    /// File name the program gets (rs274 treats a file that only defines the subroutine of
    /// its own name as a call of it).
    pub program_name: String,
}

impl Default for Rs274Options {
    fn default() -> Self {
        Rs274Options {
            timeout: Duration::from_secs(60),
            max_output: 1 << 30,
            sub_dirs: Vec::new(),
            tool_table: None,
            program_name: "program.ngc".into(),
        }
    }
}

/// What rs274 wrote.
#[derive(Clone, Debug, Default)]
#[non_exhaustive]
pub struct Rs274Output {
    /// Canonical machining commands, one per line.
    pub stdout: String,
    /// Error messages, each followed by the block it echoes.
    pub stderr: String,
}

impl Rs274Output {
    /// Standard output, a newline, then standard error: the text
    /// [`super::linuxcnc::parse_canon`] reads (errors after the moves they stopped).
    #[must_use]
    pub fn combined(&self) -> String {
        let mut s = String::with_capacity(self.stdout.len() + self.stderr.len() + 1);
        s.push_str(&self.stdout);
        s.push('\n');
        s.push_str(&self.stderr);
        s
    }
}

/// Why rs274 gave no reading.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Rs274Error {
    /// The program could not be started (not installed, or not executable).
    #[error("cannot run rs274 (install the Debian package linuxcnc-uspace): {0}")]
    NotRunnable(#[source] std::io::Error),
    /// The temporary folder or a file in it could not be made or read.
    #[error("{what} {}: {source}", path.display())]
    Io {
        /// What was being done.
        what: &'static str,
        /// The file or folder.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// rs274 used more than [`Rs274Options::timeout`] of processor time (of wall time where
    /// processor time cannot be read).
    #[error(
        "rs274 did not finish within {:.1} s of processor time: stopped (a runaway loop? \
         raise --rs274-timeout if the program is just long)", .0.as_secs_f64()
    )]
    Timeout(Duration),
    /// rs274 was still running after 30 times (`WALL_BACKSTOP_FACTOR`)
    /// [`Rs274Options::timeout`] of wall time without reaching its processor-time limit.
    #[error(
        "rs274 was still running after {:.1} s of wall time without using its processor \
         time: stopped (blocked?)", .0.as_secs_f64()
    )]
    Stalled(Duration),
    /// rs274 wrote more than [`Rs274Options::max_output`] bytes.
    #[error("rs274 wrote more than {} MB: stopped (a runaway loop?)", .0 >> 20)]
    OutputTooLarge(u64),
    /// rs274 was killed by a signal: its reading is incomplete.
    #[error("rs274 was killed by signal {0}: its reading is incomplete")]
    Killed(i32),
    /// rs274 wrote nothing at all.
    #[error("rs274 produced no output")]
    NoOutput,
}

/// Runs `rs274 -n 0 -g` on `text` as it is (number its lines first with
/// [`super::linuxcnc::number_lines`] for findings with source lines) in a folder of its own.
pub fn run(text: &str, opts: &Rs274Options) -> Result<Rs274Output, Rs274Error> {
    let tmp = std::env::temp_dir();
    super::temp::remove_left_behind(&tmp, TMP_PREFIX);
    let dir = own_tmp_dir(&tmp)?;
    let io = |what: &'static str, path: &Path| {
        let path = path.to_path_buf();
        move |source| Rs274Error::Io { what, path, source }
    };
    let name = Path::new(&opts.program_name)
        .file_name()
        .unwrap_or("program.ngc".as_ref());
    let file = dir.0.join(name);
    std::fs::write(&file, text).map_err(io("cannot write", &file))?;
    for d in &opts.sub_dirs {
        copy_subroutines(d, &dir.0);
    }
    let out_path = dir.0.join("out.txt");
    let err_path = dir.0.join("err.txt");
    let out = std::fs::File::create(&out_path).map_err(io("cannot create", &out_path))?;
    let err = std::fs::File::create(&err_path).map_err(io("cannot create", &err_path))?;
    let mut cmd = Command::new("rs274");
    if let Some(t) = &opts.tool_table {
        cmd.arg("-t").arg(t);
    }
    let mut child = cmd
        .args(["-n", "0", "-g"])
        .arg(&file)
        .current_dir(&dir.0)
        .env("HOME", &dir.0)
        .stdin(Stdio::null())
        .stdout(Stdio::from(out))
        .stderr(Stdio::from(err))
        .spawn()
        .map_err(Rs274Error::NotRunnable)?;
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child
            .try_wait()
            .map_err(io("cannot wait for rs274 in", &dir.0))?
        {
            break status;
        }
        let size = std::fs::metadata(&out_path).map(|m| m.len()).unwrap_or(0);
        let wall = start.elapsed();
        let stop = if size > opts.max_output {
            Some(Rs274Error::OutputTooLarge(opts.max_output))
        } else {
            match processor_time(child.id()) {
                Some(cpu) if cpu > opts.timeout => Some(Rs274Error::Timeout(opts.timeout)),
                Some(_) if wall > opts.timeout * WALL_BACKSTOP_FACTOR => {
                    Some(Rs274Error::Stalled(opts.timeout * WALL_BACKSTOP_FACTOR))
                }
                None if wall > opts.timeout => Some(Rs274Error::Timeout(opts.timeout)),
                _ => None,
            }
        };
        if let Some(e) = stop {
            let _ = child.kill();
            let _ = child.wait();
            return Err(e);
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    if let Some(signal) = killed_by(&status) {
        return Err(Rs274Error::Killed(signal));
    }
    let read = |p: &Path| {
        std::fs::read(p)
            .map(|b| String::from_utf8_lossy(&b).into_owned())
            .map_err(io("cannot read", p))
    };
    let output = Rs274Output {
        stdout: read(&out_path)?,
        stderr: read(&err_path)?,
    };
    if output.stdout.trim().is_empty() && output.stderr.trim().is_empty() {
        return Err(Rs274Error::NoOutput);
    }
    Ok(output)
}

/// Processor time (user + system) process `pid` has used so far: fields 14 and 15 of
/// `/proc/PID/stat` (proc(5)) over [`USER_HZ`]; `None` where that file cannot be read or
/// parsed. The fields are counted after the command name's closing parenthesis, since the
/// name itself may hold spaces.
fn processor_time(pid: u32) -> Option<Duration> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat")).ok()?;
    parse_processor_time(&stat)
}

/// [`processor_time`] of the text of a `/proc/PID/stat` file.
fn parse_processor_time(stat: &str) -> Option<Duration> {
    let (_, after_name) = stat.rsplit_once(')')?;
    // Field 3 (state) is the first after the name: utime (14) and stime (15) follow.
    let mut fields = after_name.split_whitespace().skip(14 - 3);
    let utime: u64 = fields.next()?.parse().ok()?;
    let stime: u64 = fields.next()?.parse().ok()?;
    Some(Duration::from_secs_f64((utime + stime) as f64 / USER_HZ))
}

#[cfg(unix)]
fn killed_by(status: &std::process::ExitStatus) -> Option<i32> {
    std::os::unix::process::ExitStatusExt::signal(status)
}

#[cfg(not(unix))]
fn killed_by(_: &std::process::ExitStatus) -> Option<i32> {
    None
}

/// Copies the `.ngc` files of `from` into `to` unless a file of that name is there already.
fn copy_subroutines(from: &Path, to: &Path) {
    let Ok(rd) = std::fs::read_dir(from) else {
        return;
    };
    for e in rd.flatten() {
        let p = e.path();
        if let Some(n) = p
            .file_name()
            .filter(|_| p.extension().is_some_and(|x| x == "ngc"))
        {
            let dst = to.join(n);
            if !dst.exists() {
                let _ = std::fs::copy(&p, dst);
            }
        }
    }
}

/// Removes the temporary folder when dropped (every exit path, panics included).
struct TmpDir(PathBuf);

impl Drop for TmpDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A new folder `skinpath-rs274-PID-N` in `tmp` that no other run uses: `create_dir` fails
/// on an existing name, so concurrent runs (parallel tests, several checks in one process)
/// each get their own and cannot overwrite each other's program or output.
fn own_tmp_dir(tmp: &Path) -> Result<TmpDir, Rs274Error> {
    static NEXT: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
    loop {
        let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let path = tmp.join(format!("{TMP_PREFIX}{}-{n}", std::process::id()));
        match std::fs::create_dir(&path) {
            Ok(()) => return Ok(TmpDir(path)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && n < 10_000 => continue,
            Err(source) => {
                return Err(Rs274Error::Io {
                    what: "cannot create",
                    path,
                    source,
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A `/proc/PID/stat` line (format of proc(5)) whose command name holds spaces and a
    /// parenthesis: utime 250 and stime 75 ticks are 3.25 s.
    #[test]
    fn processor_time_reads_utime_and_stime_after_the_name() {
        let stat = "4242 (rs274 (x) y) R 1 4242 4242 0 -1 4194304 1000 0 0 0 250 75 0 0 20 0 \
                    1 0 12345 1000000 200 18446744073709551615";
        assert_eq!(
            parse_processor_time(stat),
            Some(Duration::from_secs_f64(3.25))
        );
        assert_eq!(parse_processor_time("4242 (cut"), None);
    }

    /// This process's own entry reads (on Linux); a process that does not exist has none.
    #[test]
    #[cfg(target_os = "linux")]
    fn own_processor_time_is_read() {
        assert!(processor_time(std::process::id()).is_some());
        assert_eq!(processor_time(u32::MAX), None);
    }
}
