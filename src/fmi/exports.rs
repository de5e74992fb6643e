//! The vehicle FMU's exported `fmi2…` symbols: the generic layer's, bound to `vehicle::VehicleModel`.

#![allow(non_snake_case)]
#![allow(clippy::missing_safety_doc)]

fmi_layer::export_fmi2!(super::vehicle::VehicleModel);
