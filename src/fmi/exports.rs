//! The vehicle FMU's exported `fmi2…` and `fmi3…` symbols: the generic layer's, bound to
//! `vehicle::VehicleModel`. One library serves both RtVehicle.fmu (FMI 2.0) and RtVehicle3.fmu (FMI 3.0).

#![allow(non_snake_case)]
#![allow(clippy::missing_safety_doc)]

fmi_layer::export_fmi2!(super::vehicle::VehicleModel);
fmi_layer::export_fmi3!(super::vehicle::VehicleModel);
