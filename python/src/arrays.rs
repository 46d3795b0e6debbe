//! numpy arrays in: any array-like of the right shape, converted only when
//! its dtype or layout needs it (`numpy.ascontiguousarray` returns the array
//! itself when it is already C-contiguous of that dtype, so no copy).

use numpy::{Element, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use sturmray::math::{Ray, Vec3};

use crate::errors::value_error;

/// `value` as a C-contiguous array of `dtype` ("float32", "uint32", ...).
fn contiguous<'py>(
    py: Python<'py>,
    value: &Bound<'py, PyAny>,
    dtype: &str,
) -> PyResult<Bound<'py, PyAny>> {
    py.import("numpy")?
        .call_method1("ascontiguousarray", (value, dtype))
}

/// `value` as an (N, 3) array of `dtype`; `name` is the argument's, for messages.
pub fn rows3<'py, T: Element>(
    py: Python<'py>,
    value: &Bound<'py, PyAny>,
    dtype: &str,
    name: &str,
) -> PyResult<PyReadonlyArray2<'py, T>> {
    let array = contiguous(py, value, dtype)?;
    let shape: Vec<usize> = array.getattr("shape")?.extract()?;
    if shape.len() != 2 || shape[1] != 3 {
        return Err(value_error(format!(
            "{name}: expected an (N, 3) array, found shape {shape:?}"
        )));
    }
    array.extract::<PyReadonlyArray2<'py, T>>()
}

/// `value` (a number or an (N,) array) as N float32 values.
fn per_ray<'py>(
    py: Python<'py>,
    value: &Bound<'py, PyAny>,
    n: usize,
    name: &str,
) -> PyResult<PyReadonlyArray1<'py, f32>> {
    let numpy = py.import("numpy")?;
    let broadcast = numpy
        .call_method1("broadcast_to", (contiguous(py, value, "float32")?, (n,)))
        .map_err(|_| {
            value_error(format!(
                "{name}: expected a number or an array of {n} values"
            ))
        })?;
    contiguous(py, &broadcast, "float32")?.extract()
}

/// The rays of `origins`, `directions`, `tnear` and `tfar`, checked as the
/// CLI checks a ray file (`accel::check_rays`, in the trace itself).
pub fn rays<'py>(
    py: Python<'py>,
    origins: &Bound<'py, PyAny>,
    directions: &Bound<'py, PyAny>,
    tnear: &Bound<'py, PyAny>,
    tfar: &Bound<'py, PyAny>,
) -> PyResult<Vec<Ray>> {
    let o = rows3::<f32>(py, origins, "float32", "origins")?;
    let d = rows3::<f32>(py, directions, "float32", "directions")?;
    let n = o.shape()[0];
    if d.shape()[0] != n {
        return Err(value_error(format!(
            "directions: expected {n} rows, as origins has, found {}",
            d.shape()[0]
        )));
    }
    let near = per_ray(py, tnear, n, "tnear")?;
    let far = per_ray(py, tfar, n, "tfar")?;
    let (o, d, near, far) = (
        o.as_slice()?,
        d.as_slice()?,
        near.as_slice()?,
        far.as_slice()?,
    );
    Ok((0..n)
        .map(|i| Ray {
            origin: Vec3::from_slice(&o[3 * i..3 * i + 3]),
            dir: Vec3::from_slice(&d[3 * i..3 * i + 3]),
            tnear: near[i],
            tfar: far[i],
        })
        .collect())
}
