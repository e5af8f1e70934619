//! How the components advance together over one communication step: one file per method, each
//! seeing the components only through `Slave` and the values only through `Exchange`.
//! Uses slave.rs, exchange.rs and error.rs.

pub mod gauss_seidel;
pub mod jacobi;

use crate::error::{Error, Result};

/// A coupling method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Fixed-step Jacobi: every component steps from the inputs of the last communication
    /// point, then the connections carry the new outputs.
    Jacobi,
    /// Fixed-step Gauss-Seidel: the components step in the connection graph's order, each from
    /// the newest outputs of those before it.
    GaussSeidel,
}

impl Method {
    /// Parses `jacobi` or `gauss_seidel`.
    pub fn parse(s: &str) -> Result<Method> {
        match s {
            "jacobi" => Ok(Method::Jacobi),
            "gauss_seidel" => Ok(Method::GaussSeidel),
            other => Err(Error::new(format!(
                "unknown method '{other}'; there are: jacobi, gauss_seidel"
            ))),
        }
    }
    /// The name as the command line spells it.
    pub fn name(self) -> &'static str {
        match self {
            Method::Jacobi => "jacobi",
            Method::GaussSeidel => "gauss_seidel",
        }
    }
}
