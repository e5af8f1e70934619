//! The one error type of the master: what failed, and where, as far as it is known — the
//! archive element (a file inside the SSP or the FMU, with the XML element), the component,
//! the variable, the FMI function and the simulation time. Its `Display` is the one message a
//! user reads: `archive element: component 'c': variable 'v': fmi2DoStep at t = 0.5: cause`.
//! Uses only std.

use std::fmt;

/// A failure of the master, with its context filled in as it travels up.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Error {
    /// The file inside the archive (and XML element), e.g. `SystemStructure.ssd: <ssd:Connection>`.
    pub element: Option<String>,
    /// The component (instance) name.
    pub component: Option<String>,
    /// The variable (or connector) name.
    pub variable: Option<String>,
    /// The FMI function that failed.
    pub function: Option<String>,
    /// The simulation time at which it failed.
    pub time: Option<f64>,
    /// What went wrong.
    pub cause: String,
}

/// The master's result type.
pub type Result<T> = std::result::Result<T, Error>;

impl Error {
    /// An error with its cause only; the context is added by the `with_*` methods.
    pub fn new(cause: impl Into<String>) -> Self {
        Error {
            cause: cause.into(),
            ..Default::default()
        }
    }
    /// Names the archive element, unless a more precise one is already set.
    pub fn element(mut self, e: impl Into<String>) -> Self {
        self.element.get_or_insert_with(|| e.into());
        self
    }
    /// Names the component, unless already set.
    pub fn component(mut self, c: impl Into<String>) -> Self {
        self.component.get_or_insert_with(|| c.into());
        self
    }
    /// Names the variable, unless already set.
    pub fn variable(mut self, v: impl Into<String>) -> Self {
        self.variable.get_or_insert_with(|| v.into());
        self
    }
    /// Names the FMI function, unless already set.
    pub fn function(mut self, f: impl Into<String>) -> Self {
        self.function.get_or_insert_with(|| f.into());
        self
    }
    /// Sets the simulation time, unless already set.
    pub fn at(mut self, t: f64) -> Self {
        self.time.get_or_insert(t);
        self
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(e) = &self.element {
            write!(f, "{e}: ")?;
        }
        if let Some(c) = &self.component {
            write!(f, "component '{c}': ")?;
        }
        if let Some(v) = &self.variable {
            write!(f, "variable '{v}': ")?;
        }
        match (&self.function, self.time) {
            (Some(func), Some(t)) => write!(f, "{func} at t = {t}: ")?,
            (Some(func), None) => write!(f, "{func}: ")?,
            (None, Some(t)) => write!(f, "at t = {t}: ")?,
            (None, None) => {}
        }
        write!(f, "{}", self.cause)
    }
}

impl std::error::Error for Error {}

/// Attaches context to any `Result<T, Error>`.
pub trait Context<T> {
    /// Adds the component name to the error.
    fn in_component(self, c: &str) -> Result<T>;
    /// Adds the archive element to the error.
    fn in_element(self, e: &str) -> Result<T>;
}

impl<T> Context<T> for Result<T> {
    fn in_component(self, c: &str) -> Result<T> {
        self.map_err(|e| e.component(c))
    }
    fn in_element(self, e: &str) -> Result<T> {
        self.map_err(|err| err.element(e))
    }
}
