//! Studies of the vehicle that are not simulations: they use the model (`model/`) as a rig uses the car,
//! and stay out of the engine (nothing in `model/`, `dynamics/` or `sim/` imports them).
//!
//! - `chrono_compare.rs`: an import against its source's own runs (`rtv chrono-compare`, docs/vehicle_file.md).
//! - `kc.rs`: the kinematics-and-compliance report (`rtv kc`, docs/kc/).
//! - `linear.rs`: the vehicle linearized about a steady state: modes, understeer gradient, yaw-rate gain
//!   (`rtv linearize`, docs/linear.md).
//! - `manoeuvres.rs`: the standard open- and closed-loop manoeuvres and their metrics (`rtv manoeuvre`,
//!   docs/manoeuvres.md); the closed loop drives with the `rtv-driver` crate.
//! - `stability.rs`: the stability suite (`rtv stability`, docs/stability.md).
//! - `ride.rs`, `ride_filters.rs`: the NRMM ride tests (`rtv ride`, docs/ride.md).
//! - `work_precision.rs`: error against run time (`rtv work-precision`, docs/work_precision.md).
//! - `study_run.rs`: one run of a parameter study (python/rtv_study through crates/study-native, docs/studies.md).
//!
//! They are the Cargo feature `studies` (default on: the CLI, the tests): the FMU's library is built without
//! it (packaging: `--no-default-features`), so it carries neither the studies nor the driver crate.

pub mod calibration;
pub mod chrono_compare;
pub mod kc;
pub mod linear;
pub mod manoeuvres;
pub mod ride;
pub mod ride_filters;
pub mod scenes;
pub mod shipped_calibration;
pub mod stability;
pub mod study_run;
pub mod work_precision;

/// The process's CPU time (user + system), in seconds: what the time figures of the studies and the CLI
/// measure. The wall clock would count the other jobs of a shared machine too (on this project's busy
/// 2-core machine it read twice the CPU time).
pub fn cpu_seconds() -> f64 {
    let mut t = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    // SAFETY: `t` is a valid timespec for the call to write into.
    if unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) } != 0 {
        return f64::NAN;
    }
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// The machine and the date (UTC) that a doc's time figures name: "AMD EPYC, 2 cores available, Linux
/// 6.18.44, 2026-11-27". The same words as `scripts/docs_check.py machine`, which the shell scripts use.
pub fn machine() -> String {
    let read = |path: &str| std::fs::read_to_string(path).unwrap_or_default();
    let cpuinfo = read("/proc/cpuinfo");
    let model = cpuinfo
        .lines()
        .find_map(|l| l.strip_prefix("model name").and_then(|r| r.split_once(':')).map(|(_, m)| m.trim().to_string()))
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let release = read("/proc/sys/kernel/osrelease");
    let days =
        std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH).map_or(0, |d| (d.as_secs() / 86_400) as i64);
    let (y, m, d) = civil_date(days);
    format!("{model}, {cores} cores available, Linux {}, {y:04}-{m:02}-{d:02}", release.trim())
}

/// Year, month, day of a day count since 1970-01-01 (the proleptic Gregorian calendar; H. Hinnant's
/// `civil_from_days`).
fn civil_date(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

#[cfg(test)]
mod tests {
    #[test]
    fn civil_dates() {
        assert_eq!(super::civil_date(0), (1970, 1, 1));
        assert_eq!(super::civil_date(11_016), (2000, 2, 29)); // a leap day of a century divisible by 400
        assert_eq!(super::civil_date(20_819), (2027, 1, 1));
        assert_eq!(super::civil_date(-1), (1969, 12, 31));
    }

    #[test]
    fn cpu_time_advances_with_work() {
        let t0 = super::cpu_seconds();
        let mut x = 0u64;
        for i in 0..20_000_000u64 {
            x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(i));
        }
        assert!(super::cpu_seconds() > t0, "{x}");
    }
}
