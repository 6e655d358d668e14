//! The process's peak memory and CPU time, for the run summary: the
//! high-water mark of its resident set (`VmHWM` in `/proc/self/status`,
//! Linux; see proc(5)) and its user plus system time (getrusage(2),
//! `RUSAGE_SELF`: every thread). `None` where the system does not report
//! them.

/// Peak resident memory of this process so far (MiB).
pub fn peak_resident_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    parse_vm_hwm_kib(&status).map(|kib| kib / 1024.0)
}

/// CPU time of this process so far, user plus system, every thread (s).
pub fn process_cpu_time_s() -> Option<f64> {
    let mut usage = std::mem::MaybeUninit::<libc::rusage>::zeroed();
    // SAFETY: getrusage writes a `rusage` into the pointer it is given, and
    // `usage` is one, zero-initialised; it is read only on success.
    let rc = unsafe { libc::getrusage(libc::RUSAGE_SELF, usage.as_mut_ptr()) };
    if rc != 0 {
        return None;
    }
    // SAFETY: initialised (zeroed, then filled by a successful call).
    let usage = unsafe { usage.assume_init() };
    let seconds = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    Some(seconds(usage.ru_utime) + seconds(usage.ru_stime))
}

/// The `VmHWM:  1234 kB` line of a `/proc/<pid>/status` text (kB are KiB
/// there).
fn parse_vm_hwm_kib(status: &str) -> Option<f64> {
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let mut words = line["VmHWM:".len()..].split_whitespace();
    let value: f64 = words.next()?.parse().ok()?;
    (words.next() == Some("kB")).then_some(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_high_water_mark_line_is_read_in_kib() {
        let status = "Name:\tsim\nVmPeak:\t  999 kB\nVmHWM:\t   20480 kB\nVmRSS:\t 100 kB\n";
        assert_eq!(parse_vm_hwm_kib(status), Some(20480.0));
        assert_eq!(parse_vm_hwm_kib("VmHWM: 12 MB\n"), None);
        assert_eq!(parse_vm_hwm_kib("Name: x\n"), None);
    }

    #[test]
    fn this_process_has_a_peak_on_linux() {
        if std::path::Path::new("/proc/self/status").exists() {
            let mib = peak_resident_mib().expect("VmHWM on Linux");
            assert!(mib > 1.0 && mib < 1e6, "{mib}");
        }
    }
}
