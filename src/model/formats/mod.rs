//! The files the model reads and writes: the vehicle file (`vehicle_file`, reading; `params`, its serde
//! structs and the checks of the data alone), Chrono::Vehicle's JSON (`import_chrono`, `rtv import-chrono`)
//! and Pacejka's `.tir` tire property files (`tir`). The model's physics sits beside this folder: what a
//! format needs of it (the loop closure of a suspension, the Magic Formula built from a `.tir`) it imports.

pub mod chrono_json;
pub mod import_chrono;
pub mod params;
pub mod tir;
pub mod vehicle_file;
