//! Steady-state tire curves of the STI model with the shipped data (the paper's Fig. 3), and the
//! docs/physics.md §6.5 reference-table comparison.
//!
//! `cargo run --release --example tire_curves -- OUT.csv` writes one row per point:
//! `sweep,fz_N,kappa,alpha_rad,fx_N,fy_N,mz_Nm`, where `sweep` is `kappa` (F_x against κ at α = 0) or
//! `alpha` (F_y and M_z against α at κ = 0). Then `scripts/plot_tire_curves.py OUT.csv OUT.png` draws them.
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::tire::{shear_forces, SlipInput, TireModel, TireParams};
use std::fmt::Write as _;
use std::process::ExitCode;

/// Loads of the figure, N.
const LOADS_N: [f64; 4] = [3000.0, 6300.0, 9500.0, 12600.0];
const KAPPA_RANGE: f64 = 1.0;
const ALPHA_RANGE_RAD: f64 = 0.35; // ≈ 20°
const POINTS_PER_SIDE: i32 = 200;

fn curves_csv(p: &TireParams) -> String {
    let mut csv = String::from("sweep,fz_N,kappa,alpha_rad,fx_N,fy_N,mz_Nm\n");
    for &fz in &LOADS_N {
        for i in -POINTS_PER_SIDE..=POINTS_PER_SIDE {
            let fraction = f64::from(i) / f64::from(POINTS_PER_SIDE);
            for (sweep, kappa, alpha) in
                [("kappa", KAPPA_RANGE * fraction, 0.0), ("alpha", 0.0, ALPHA_RANGE_RAD * fraction)]
            {
                let f = shear_forces(TireModel::Sti, p, &SlipInput::rolling(fz, kappa, f64::tan(alpha), 0.0));
                // Writing to a String cannot fail.
                let _ = writeln!(csv, "{sweep},{fz},{kappa},{alpha},{},{},{}", f.fx, f.fy, f.mz);
            }
        }
    }
    csv
}

use rt_vehicle::model::tire::sti::REFERENCE;

/// Markdown table of the model against the reference (relative error, or the absolute value for a 0 entry).
fn reference_comparison(p: &TireParams) -> String {
    let mut table = String::from(
        "| F_z [N] | α [rad] | κ | γ_w [rad] | F_x [N] | F_y [N] | M_z [N·m] | max rel. error |\n|---|---|---|---|---|---|---|---|\n",
    );
    for ([fz, alpha, kappa, gamma], expected) in REFERENCE {
        let f = shear_forces(TireModel::Sti, p, &SlipInput::rolling(fz, kappa, alpha.tan(), gamma));
        let got = [f.fx, f.fy, f.mz];
        let worst = got
            .iter()
            .zip(expected.iter())
            .filter(|(_, &want)| want != 0.0)
            .map(|(&g, &want)| ((g - want) / want).abs())
            .fold(0.0, f64::max);
        let _ = writeln!(
            table,
            "| {fz} | {alpha} | {kappa} | {gamma} | {:.5} | {:.5} | {:.5} | {worst:.1e} |",
            got[0], got[1], got[2]
        );
    }
    table
}

fn main() -> ExitCode {
    let Some(out) = std::env::args().nth(1) else {
        eprintln!("usage: cargo run --example tire_curves -- OUT.csv");
        return ExitCode::FAILURE;
    };
    let p = VehicleData::default_hmmwv().tire;
    // The documented command writes into out/, which a fresh checkout does not have.
    if let Some(dir) = std::path::Path::new(&out).parent().filter(|d| !d.as_os_str().is_empty()) {
        if let Err(e) = std::fs::create_dir_all(dir) {
            eprintln!("cannot create {}: {e}", dir.display());
            return ExitCode::FAILURE;
        }
    }
    if let Err(e) = std::fs::write(&out, curves_csv(&p)) {
        eprintln!("cannot write {out}: {e}");
        return ExitCode::FAILURE;
    }
    println!("wrote {out}\n\nphysics.md §6.5 reference table, this implementation:\n{}", reference_comparison(&p));
    ExitCode::SUCCESS
}
