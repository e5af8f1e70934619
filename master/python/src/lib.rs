//! The Python module `fmi_master._native`: an archive or FMU opened once (`System`), run with
//! settings and start values as often as wanted, each run's samples handed to Python as flat
//! lists that `fmi_master/__init__.py` turns into numpy arrays. A failure before the first sample
//! raises `MasterError` with the master's one message; a failure later returns the rows before it
//! with the message in `error`. Uses fmi_master's public API and pyo3.

use fmi_master::execution::{self, Settings};
use fmi_master::inputs::InputTable;
use fmi_master::observer::Memory;
use fmi_master::time::GridKind;
use fmi_master::Method;
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// (name, type, causality, start) of one variable.
type VariableRow = (String, String, String, Option<String>);

create_exception!(
    _native,
    MasterError,
    PyException,
    "A bad archive, FMU, value or setting: the master's message."
);

fn err(e: fmi_master::Error) -> PyErr {
    MasterError::new_err(e.to_string())
}

/// An SSP archive or an FMU, opened and checked.
#[pyclass(unsendable)]
struct System {
    inner: fmi_master::System,
}

#[pymethods]
impl System {
    #[new]
    fn new(path: &str) -> PyResult<Self> {
        Ok(System {
            inner: fmi_master::System::open(std::path::Path::new(path)).map_err(err)?,
        })
    }

    /// The system's name.
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// True for a lone FMU (columns are plain variable names).
    #[getter]
    fn lone(&self) -> bool {
        self.inner.lone
    }

    /// The components' names.
    fn components(&self) -> Vec<String> {
        self.inner
            .components
            .iter()
            .map(|c| c.name.clone())
            .collect()
    }

    /// The variables of `component`: (name, type, causality, start).
    fn variables(&self, component: &str) -> PyResult<Vec<VariableRow>> {
        let c = self
            .inner
            .components
            .iter()
            .position(|c| c.name == component)
            .ok_or_else(|| MasterError::new_err(format!("no component '{component}'")))?;
        Ok(self
            .inner
            .md(c)
            .variables
            .iter()
            .map(|v| {
                (
                    v.name.clone(),
                    format!("{:?}", v.ty),
                    v.causality.name().to_string(),
                    v.start.clone(),
                )
            })
            .collect())
    }

    /// (start, stop, step) of the DefaultExperiment (and OSP's base step), each None if absent.
    fn default_experiment(&self) -> (Option<f64>, Option<f64>, Option<f64>) {
        (self.inner.start, self.inner.stop, self.inner.step)
    }

    /// Runs the system; a dict of the samples and the outcome.
    #[pyo3(signature = (method="jacobi", step=None, stop=None, interval=None, grid="exact", start_values=Vec::new(), input=None, profile=false))]
    #[allow(clippy::too_many_arguments)]
    fn run<'py>(
        &mut self,
        py: Python<'py>,
        method: &str,
        step: Option<f64>,
        stop: Option<f64>,
        interval: Option<f64>,
        grid: &str,
        start_values: Vec<(String, String)>,
        input: Option<String>,
        profile: bool,
    ) -> PyResult<Bound<'py, PyDict>> {
        let settings = Settings {
            method: Method::parse(method).map_err(err)?,
            step,
            stop,
            interval,
            grid: GridKind::parse(grid).map_err(err)?,
            profile,
            log: false,
        };
        let table = match &input {
            None => None,
            Some(file) => {
                if !self.inner.lone {
                    return Err(MasterError::new_err("an input file drives a lone FMU; an archive's inputs come from its connections"));
                }
                let text = std::fs::read_to_string(file)
                    .map_err(|e| MasterError::new_err(format!("{file}: cannot read it: {e}")))?;
                Some(InputTable::parse(&text, file, self.inner.md(0)).map_err(err)?)
            }
        };
        // start values hold for this run only
        let saved: Vec<_> = self
            .inner
            .components
            .iter()
            .map(|c| c.starts.clone())
            .collect();
        let result = (|| -> Result<_, Box<fmi_master::Error>> {
            for (name, value) in &start_values {
                self.inner
                    .add_start(name, value, "start_values")
                    .map_err(Box::new)?;
            }
            let mut memory = Memory::default();
            let outcome = execution::run(&self.inner, &settings, table.as_ref(), &mut memory)
                .map_err(Box::new)?;
            Ok((memory, outcome))
        })();
        for (c, starts) in self.inner.components.iter_mut().zip(saved) {
            c.starts = starts;
        }
        let (memory, o) = result.map_err(|e| err(*e))?;
        let d = PyDict::new(py);
        d.set_item("columns", memory.columns)?;
        d.set_item("time", memory.time)?;
        d.set_item("values", memory.values)?;
        d.set_item("strings", memory.strings)?;
        d.set_item("steps", o.steps)?;
        d.set_item("step", o.step)?;
        d.set_item("calls", o.calls)?;
        d.set_item("cpu", o.cpu)?;
        d.set_item("cpu_per_second", o.cpu_per_second())?;
        d.set_item("wall", o.wall)?;
        d.set_item("fmu_time", o.fmu_time)?;
        d.set_item("end", o.end)?;
        d.set_item("terminated", o.terminated)?;
        d.set_item("error", o.error.map(|e| e.to_string()))?;
        Ok(d)
    }
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<System>()?;
    m.add("MasterError", m.py().get_type::<MasterError>())?;
    Ok(())
}
