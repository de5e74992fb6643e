//! A model description's variables, as the generic layer reads them. Each FMU crate generates its table
//! from its `modelDescription.xml` at build time (`codegen`, called by the crate's `build.rs`): the XML is
//! the one source of names, value references, causalities, types and start values.

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    Input,
    Output,
    Parameter,
    CalculatedParameter,
    Local,
    Independent,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Initial {
    Exact,
    Approx,
    Calculated,
    /// No `initial` attribute applies (inputs, independent).
    None,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VarType {
    Real,
    Integer,
    Boolean,
    String,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Start {
    Real(f64),
    Integer(i32),
    Boolean(bool),
    String(&'static str),
}

/// One ScalarVariable of the model description. `K` is the model's own generated `Var` (which input,
/// parameter or local this is), so that a model's `match` over its variables is exhaustive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Variable<K: 'static> {
    /// Position in the description's `variables` (the XML index minus one).
    pub index: usize,
    pub name: &'static str,
    pub vr: u32,
    pub causality: Causality,
    pub variability: Variability,
    pub initial: Initial,
    pub ty: VarType,
    pub start: Option<Start>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub unit: Option<&'static str>,
    /// The `nominal` attribute of a Real, if given.
    pub nominal: Option<f64>,
    /// Which variable this is, for exhaustive matches.
    pub var: K,
}

/// A Real input that is a derivative of another Real input, as the 2.0 model description's `VendorAnnotations`
/// declare it (`codegen`): an ordinary FMI 2.0 input variable, written in the 3.0 model description with
/// `derivative="…"` (FMI 3.0 has no `fmi2SetRealInputDerivatives`; an importer sets the derivative as this
/// variable). What it means for a step is the model's business (it knows its interface: `ModelContext`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InputDerivative {
    pub name: &'static str,
    /// The value reference of the input variable that holds the derivative.
    pub vr: u32,
    /// The value reference of the input it is a derivative of.
    pub of: u32,
    /// 1 or 2.
    pub order: i32,
}

/// What the generic layer needs of a model description (generated from the XML by `codegen`).
#[derive(Debug)]
pub struct Description<K: 'static> {
    /// The `guid` attribute, checked in fmi2Instantiate and in serialized states.
    pub guid: &'static str,
    pub model_identifier: &'static str,
    /// The declared `LogCategories`, in order.
    pub log_categories: &'static [&'static str],
    /// Every ScalarVariable, in XML order.
    pub variables: &'static [Variable<K>],
    /// The index in `variables` of a value reference (a generated `match`), `None` if unknown.
    pub index_of: fn(u32) -> Option<usize>,
    /// The inputs that are derivatives of other inputs (none in an FMU that does not declare them).
    pub input_derivatives: &'static [InputDerivative],
    /// Model Exchange: the continuous states, in the order of the state vector (the order of the model
    /// structure's `Derivatives`), as indices into `variables`.
    pub states: &'static [usize],
    /// The state derivatives, `derivatives[k]` the derivative of `states[k]`, as indices into `variables`.
    pub derivatives: &'static [usize],
    /// The event indicators, in the order of the indicator vector, as indices into `variables`.
    pub event_indicators: &'static [usize],
    /// The model description declares `<ModelExchange>`.
    pub model_exchange: bool,
    /// The value reference of FMI 3.0's independent variable (time), if declared: FMI 3.0 requires one,
    /// the FMI 2.0 description has none.
    pub independent_vr: Option<u32>,
}

impl<K> Description<K> {
    /// Look a variable up by value reference and type (FMI value references are unique per type; ours
    /// are unique overall, and a reference asked for with the wrong type is an error).
    pub fn lookup(&self, vr: u32, ty: VarType) -> Option<&'static Variable<K>> {
        (self.index_of)(vr).map(|i| &self.variables[i]).filter(|v| v.ty == ty)
    }

    /// The position in the state vector of a continuous-state variable (index into `variables`).
    pub fn state_position(&self, index: usize) -> Option<usize> {
        self.states.iter().position(|&s| s == index)
    }

    pub fn by_name(&self, name: &str) -> Option<&'static Variable<K>> {
        self.variables.iter().find(|v| v.name == name)
    }
}
