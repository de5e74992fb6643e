//! Suspension subsystems. Each corner is one SLA (double wishbone) subsystem of the synthesis method.

pub mod sla;
