//! Instructions per tire force evaluation (`model::tire::shear_forces` plus the rolling resistance), STI
//! against the Magic Formula of a `.tir` file, free of machine noise: callgrind counts only `measured` (the N
//! evaluations), and the count divided by N is one evaluation. `bash scripts/instructions.sh` runs it
//! (docs/results.md, "Instructions"; from a fixed-length path in an empty environment, so that the
//! count repeats: `examples/evaluation_instructions.rs` says why); by hand:
//!
//! ```sh
//! cargo build --release --example tire_instructions
//! for m in sti resources/tires/HMMWV_Pac02Tire.tir; do valgrind --tool=callgrind --collect-atstart=no \
//!     --toggle-collect='*measured*' --callgrind-out-file=/tmp/cg.tire target/release/examples/tire_instructions \
//!     $m 20000 2>&1 | grep "Collected"; done
//! ```
//! The inputs cycle through a cornering state's four wheels (loads 4–8 kN, small slips, camber), as the
//! J-turn presents them, so that no branch is predicted from one repeated input.
use rt_vehicle::model::formats::params::VehicleData;
use rt_vehicle::model::tire::TireParams;
use rt_vehicle::model::tire::{self, SlipInput, TireModel, TireSide};
use std::hint::black_box;

fn main() {
    let mut args = std::env::args().skip(1);
    let which = args.next().unwrap_or_else(|| "sti".into());
    let n: usize = args.next().and_then(|a| a.parse().ok()).unwrap_or(20_000);
    let mut data = VehicleData::default_hmmwv();
    let model = if which == "sti" {
        TireModel::Sti
    } else {
        data.use_tire_file(std::path::Path::new(&which)).unwrap();
        TireModel::MagicFormula
    };
    let p = data.tire.clone();
    let wheels = [
        SlipInput { side: TireSide::Left, ..SlipInput::rolling(4100.0, 0.004, 0.021, 0.012) },
        SlipInput { side: TireSide::Right, ..SlipInput::rolling(8200.0, 0.006, 0.026, -0.018) },
        SlipInput { side: TireSide::Left, ..SlipInput::rolling(4500.0, 0.011, 0.017, 0.004) },
        SlipInput { side: TireSide::Right, ..SlipInput::rolling(7600.0, 0.012, 0.019, -0.006) },
    ];
    let sum = measured(n, model, &p, &wheels);
    println!("{which}: {n} evaluations, checksum {sum}");
}

/// The N evaluations, the only code callgrind counts (`--toggle-collect='*measured*'`).
#[inline(never)]
fn measured(n: usize, model: TireModel, p: &TireParams, wheels: &[SlipInput; 4]) -> f64 {
    let mut sum = 0.0;
    for i in 0..n {
        let input = black_box(wheels[i % 4]);
        let f = tire::shear_forces(model, p, &input);
        let m_rr = tire::rolling_resistance_moment(p, input.fz, 0.45, 60.0, f.fx, 27.0, input.inclination);
        sum += f.fx + f.fy + f.mz + f.mx + m_rr;
    }
    sum
}
