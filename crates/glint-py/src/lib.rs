//! `glint._glint`: the Python module's native core (the package `glint` re-exports it; see
//! crates/glint-py/python/glint and docs/python.md). Scenes load from files or from a dict of
//! the native format's schema; renders come back as numpy arrays, rendered with the GIL
//! released and stopped by Ctrl-C; a render of a sample range comes back as a `Partial`,
//! which pickles (for Ray) and merges bit for bit; `compare` judges an image against a
//! reference.
//!
//! A load and a render are the command's own render job (`glint_cli::job`): the same checks
//! and limits (the memory limit, GLINT_MEMORY_LIMIT, the thread bound) with the same words
//! (arguments named as Python names them), the same identity (a part rendered here merges
//! with one from `glint render --samples`), and the same warnings, issued as
//! `glint.GlintWarning`s. This module only turns Python's arguments into a request, runs the
//! job with the GIL released, and hands back numpy arrays.

use std::ffi::CString;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Arc};
use std::time::Duration;

use glint_cli::compare as judge;
use glint_cli::description::{self, Description, DescriptionError};
use glint_cli::error::CliError;
use glint_cli::job::{self, FrontEnd, Job, Plan, Request, SceneOverrides, SceneSource};
use glint_cli::limits;
use glint_cli::partial::{self, Partial as PartialFile};
use glint_core::film::Film;
use glint_core::integrators::aov::Aovs;
use glint_core::integrators::IntegratorKind;
use glint_core::render::RenderOutput;
use glint_core::{Named, Rgb};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyTypeError, PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyBytes, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

// Named `glint.…`, where the package exports them, so that they pickle (a worker process's
// error reaches its parent).
create_exception!(glint, GlintError, PyException, "A scene, render or file glint refuses; the message says why.");
create_exception!(
    glint,
    GlintWarning,
    PyUserWarning,
    "Something worth knowing about a scene or render that does not stop it (the warnings `glint render` prints)."
);

fn glint_error(e: impl std::fmt::Display) -> PyErr {
    GlintError::new_err(e.to_string())
}

/// A refusal of the render job: an argument out of its range or in conflict (`ValueError`),
/// or a scene, render or file glint refuses (`GlintError`).
fn job_error(e: CliError) -> PyErr {
    match e {
        CliError::Setting(message) => PyValueError::new_err(message),
        other => glint_error(other),
    }
}

/// Each message as a `GlintWarning`, attributed to the caller's line.
fn warn_all(py: Python<'_>, messages: &[String]) -> PyResult<()> {
    let category = py.get_type::<GlintWarning>();
    for message in messages {
        let text = CString::new(message.replace('\0', " ")).unwrap_or_default();
        PyErr::warn(py, category.as_any(), &text, 1)?;
    }
    Ok(())
}

/// A path argument: a str, bytes or path-like object (as `open` takes).
fn path_argument(value: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
    value.py().import("os")?.call_method1("fsdecode", (value,))?.extract()
}

/// The memory limit (GLINT_MEMORY_LIMIT, else the default), read at each call as the command
/// reads it at each run, and handed to the scene readers.
fn memory_limit() -> PyResult<u64> {
    job::memory_limit(None).map_err(glint_error)
}

/// An integer argument (a Python int, a numpy integer: anything with `__index__`) as its
/// value, if it fits, and its decimal text.
fn integer_argument(value: &Bound<'_, PyAny>, name: &str) -> PyResult<(Option<i128>, String)> {
    let index = value.py().import("operator")?.call_method1("index", (value,)).map_err(|_| {
        let kind = value.get_type().name().map(|n| n.to_string()).unwrap_or_default();
        let shown = value.repr().map(|r| r.to_string()).unwrap_or_default();
        PyTypeError::new_err(format!("{name} must be a whole number, got {shown} (of type `{kind}`)"))
    })?;
    Ok((index.extract::<i128>().ok(), index.str()?.to_string()))
}

/// An integer argument from `min` to `max`.
fn ranged_argument(value: &Bound<'_, PyAny>, name: &str, min: u64, max: u64) -> PyResult<u64> {
    match integer_argument(value, name)? {
        (Some(n), _) if (i128::from(min)..=i128::from(max)).contains(&n) => Ok(n as u64),
        (_, shown) => {
            Err(PyValueError::new_err(format!("{name} must be a whole number from {min} to {max}, got {shown}")))
        }
    }
}

/// `samples`: any pair of sample indices (a tuple, a list, a numpy array).
fn samples_argument(value: &Bound<'_, PyAny>) -> PyResult<(u32, u32)> {
    let shown = || value.repr().map(|r| r.to_string()).unwrap_or_default();
    let not_a_pair =
        || PyValueError::new_err(format!("samples must be a pair (a, b) of sample indices, got {}", shown()));
    if value.is_instance_of::<PyString>() || value.is_instance_of::<PyBytes>() {
        return Err(not_a_pair());
    }
    // At most three items: enough to tell a pair, and an endless iterator ends.
    let items = value.try_iter().map_err(|_| not_a_pair())?.take(3).collect::<PyResult<Vec<_>>>()?;
    let [a, b] = items.as_slice() else { return Err(not_a_pair()) };
    let a = ranged_argument(a, "samples: a", 0, u64::from(u32::MAX))? as u32;
    let b = ranged_argument(b, "samples: b", 0, u64::from(u32::MAX))? as u32;
    Ok((a, b))
}

/// A loaded scene and the render settings it asks for: the render job's scene, which every
/// render of it starts from.
#[pyclass(module = "glint._glint", frozen)]
struct Scene {
    job: Arc<Job>,
    /// The scene's contents and parameters when it was read (`Job::source_fingerprint`): a
    /// pickled scene read again must be the same.
    source_fingerprint: u64,
}

/// An image as a (height, width, 3) float32 array.
fn image_array<'py>(py: Python<'py>, width: u32, height: u32, pixels: &[Rgb]) -> PyResult<Bound<'py, PyAny>> {
    let flat: Vec<f32> = pixels.iter().flat_map(|p| p.to_array()).collect();
    Ok(PyArray1::from_vec(py, flat).reshape([height as usize, width as usize, 3])?.into_any())
}

/// One value per pixel as a (height, width) float32 array.
fn scalar_array<'py>(py: Python<'py>, width: u32, height: u32, values: Vec<f32>) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, values).reshape([height as usize, width as usize])?.into_any())
}

impl Scene {
    /// Loads `source` within the memory limit, warning what the readers warn about.
    fn load(py: Python<'_>, source: SceneSource) -> PyResult<Self> {
        memory_limit()?;
        let (job, warnings) = Job::load(source, &SceneOverrides::default()).map_err(glint_error)?;
        warn_all(py, &warnings)?;
        // The files by content now, as they were read (a render's identity reuses it).
        let source_fingerprint = job.source_fingerprint();
        Ok(Self { job: Arc::new(job), source_fingerprint })
    }
}

#[pymethods]
impl Scene {
    #[getter]
    fn width(&self) -> u32 {
        self.job.scene().camera().width
    }

    #[getter]
    fn height(&self) -> u32 {
        self.job.scene().camera().height
    }

    /// The scene's own settings: spp, seed, integrator, sampler, filter.
    #[getter]
    fn settings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let options = self.job.options();
        let d = PyDict::new(py);
        d.set_item("spp", options.spp)?;
        d.set_item("seed", options.seed)?;
        d.set_item("integrator", options.integrator.name())?;
        d.set_item("sampler", options.sampler.name())?;
        d.set_item("filter", options.filter.name())?;
        Ok(d)
    }

    /// Renders the camera's view. Without `samples`: the image as a (height, width, 3)
    /// float32 array (with `aovs=True`, a dict of it, the AOVs and, for camera integrators,
    /// the variance). With `samples=(a, b)`: samples a to b − 1 of every pixel, as a `Partial`
    /// to merge with the others (from Python or `glint render --samples`). `threads`: 1 to
    /// 1024 worker threads (default: all cores). The render job of `glint render` runs it:
    /// its checks, its memory limit (GLINT_MEMORY_LIMIT GiB, default 8), its warnings. The GIL
    /// is released while rendering; Ctrl-C stops the render and raises KeyboardInterrupt.
    #[pyo3(signature = (spp=None, seed=None, samples=None, integrator=None, threads=None, aovs=false))]
    #[allow(clippy::too_many_arguments)] // Python's keyword arguments, as Mitsuba's `render` has them
    fn render<'py>(
        &self,
        py: Python<'py>,
        spp: Option<&Bound<'py, PyAny>>,
        seed: Option<&Bound<'py, PyAny>>,
        samples: Option<&Bound<'py, PyAny>>,
        integrator: Option<&str>,
        threads: Option<&Bound<'py, PyAny>>,
        aovs: bool,
    ) -> PyResult<Bound<'py, PyAny>> {
        let threads = match threads {
            Some(value) => {
                let (_, shown) = integer_argument(value, "threads")?;
                Some(limits::parse_thread_count(&shown).map_err(PyValueError::new_err)?)
            }
            None => None,
        };
        let integrator = match integrator {
            None => None,
            Some(name) => Some(IntegratorKind::from_name(name).ok_or_else(|| {
                PyValueError::new_err(format!(
                    "unknown integrator `{name}`, expected one of {}",
                    IntegratorKind::names()
                ))
            })?),
        };
        let request = Request {
            front_end: FrontEnd::Python,
            integrator,
            spp: spp.map(|v| ranged_argument(v, "spp", 1, u64::from(u32::MAX))).transpose()?.map(|v| v as u32),
            seed: seed.map(|v| ranged_argument(v, "seed", 0, u64::MAX)).transpose()?,
            samples: samples.map(samples_argument).transpose()?,
            aovs,
            threads,
            ..Default::default()
        };
        request.check().map_err(job_error)?;
        let (plan, warnings) = self.job.plan(&request, memory_limit()?).map_err(job_error)?;
        warn_all(py, &warnings)?;
        let (output, aov, warnings) = run_interruptibly(py, self.job.clone(), plan.clone())?;
        warn_all(py, &warnings)?;
        if let Some(attributes) = self.job.partial_attributes(&plan, &output) {
            // What was rendered: a render stopped early holds the passes it finished.
            let first = plan.sample_range.map_or(0, |(a, _)| a);
            let ranges = vec![(first, first + output.spp_done)];
            let attributes = attributes
                .into_iter()
                .filter(|(k, _)| *k != partial::SAMPLES_KEY)
                .map(|(k, v)| (k.to_string(), v))
                .collect();
            let part = Partial { film: output.film, attributes, ranges };
            return Ok(Bound::new(py, part)?.into_any());
        }
        let (width, height) = (self.width(), self.height());
        let pixels = output.film.to_rgb();
        let image = image_array(py, width, height, &pixels)?;
        let Some(aov) = aov else { return Ok(image) };
        let d = PyDict::new(py);
        d.set_item("image", image)?;
        d.set_item("albedo", image_array(py, width, height, &aov.albedo)?)?;
        d.set_item("normal", image_array(py, width, height, &aov.normal)?)?;
        d.set_item("depth", scalar_array(py, width, height, aov.depth)?)?;
        if let (true, Some(variance)) = (plan.variance, job::variance(&output.film, &pixels, output.spp_done)) {
            d.set_item("variance", image_array(py, width, height, &variance)?)?;
        }
        if let (true, Some(m2)) = (plan.moment, output.film.second_moments()) {
            d.set_item("m2", image_array(py, width, height, &m2)?)?;
        }
        Ok(d.into_any())
    }

    /// Pickles as where the scene came from: unpickling reads the file (at the same path) or
    /// the description again, and refuses one whose files have changed since.
    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let restore = py.import("glint._glint")?.getattr("_restore_scene")?;
        let fingerprint = self.source_fingerprint;
        let state = match self.job.source() {
            SceneSource::File { path, defines, .. } => {
                ("file", path.clone(), defines.clone(), None::<String>, fingerprint).into_pyobject(py)?
            }
            SceneSource::Description { json, directory } => {
                ("dict", directory.clone(), Vec::<(String, String)>::new(), Some(json.text.clone()), fingerprint)
                    .into_pyobject(py)?
            }
            SceneSource::BuiltIn => return Err(glint_error("the built-in scene is not loaded from Python")),
        };
        Ok((restore, state))
    }

    /// A scene never changes: a copy is the scene itself.
    fn __copy__(slf: Bound<'_, Self>) -> Bound<'_, Self> {
        slf
    }

    fn __deepcopy__<'py>(slf: Bound<'py, Self>, _memo: &Bound<'py, PyAny>) -> Bound<'py, Self> {
        slf
    }
}

/// Renders on a thread of its own while this one, without the GIL, waits for it, taking the
/// GIL back every 50 ms to let Python handle signals: Ctrl-C raises the stop flag (the render
/// ends after the pass under way) and becomes KeyboardInterrupt. Returns the render, its AOVs
/// if planned, and the job's warnings about it.
fn run_interruptibly(py: Python<'_>, job: Arc<Job>, plan: Plan) -> PyResult<(RenderOutput, Option<Aovs>, Vec<String>)> {
    let stop = Arc::new(AtomicBool::new(false));
    let (sender, receiver) = mpsc::channel();
    // Behind a mutex: the waits below hand it to code without the GIL, which must be Sync.
    let receiver = std::sync::Mutex::new(receiver);
    let worker = {
        let stop = stop.clone();
        std::thread::spawn(move || {
            let result = job.start(&plan, &stop).map(|(mut run, mut warnings)| {
                let rendered = run.render(None, &stop, &|| {}, &mut |_, _, _| {});
                warnings.extend(rendered.warnings);
                // Not after a Ctrl-C: the caller is no longer waiting.
                let aovs = if stop.load(Ordering::Relaxed) { None } else { run.aovs() };
                (rendered.output, aovs, warnings)
            });
            let _ = sender.send(result.map_err(job_error));
        })
    };
    loop {
        let received = py.allow_threads(|| {
            receiver.lock().unwrap_or_else(|e| e.into_inner()).recv_timeout(Duration::from_millis(50))
        });
        match received {
            Ok(result) => {
                let _ = worker.join();
                return result;
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if let Err(interrupt) = py.check_signals() {
                    // The render ends after the pass under way; a second Ctrl-C while it does
                    // stops waiting for it (the thread finishes on its own).
                    stop.store(true, Ordering::Relaxed);
                    loop {
                        let done = py.allow_threads(|| {
                            receiver.lock().unwrap_or_else(|e| e.into_inner()).recv_timeout(Duration::from_millis(50))
                        });
                        if !matches!(done, Err(mpsc::RecvTimeoutError::Timeout)) {
                            let _ = worker.join();
                            break;
                        }
                        if py.check_signals().is_err() {
                            break;
                        }
                    }
                    return Err(interrupt);
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                let _ = worker.join();
                return Err(glint_error("the render thread ended without a result (a bug in glint)"));
            }
        }
    }
}

/// One sample range of a render (or several merged): the film's exact sums, what render it is
/// part of, and which samples it holds. Pickles as the partial EXR `glint merge` reads.
#[pyclass(module = "glint._glint")]
struct Partial {
    film: Film,
    attributes: Vec<(String, String)>,
    ranges: Vec<(u32, u32)>,
}

impl Partial {
    /// The header attributes, with the sample ranges held.
    fn header(&self) -> Vec<(&str, String)> {
        let mut attributes: Vec<(&str, String)> =
            self.attributes.iter().map(|(k, v)| (k.as_str(), v.clone())).collect();
        attributes.retain(|(k, _)| *k != partial::SAMPLES_KEY);
        attributes.push((partial::SAMPLES_KEY, partial::format_ranges(&self.ranges)));
        attributes
    }

    fn encode(&self) -> PyResult<Vec<u8>> {
        partial::encode(&self.film, &self.header()).map_err(glint_error)
    }

    fn from_file(file: PartialFile) -> PyResult<Self> {
        let film = Film::from_exact_sums(file.width, file.height, file.sums)
            .ok_or_else(|| glint_error("a part whose sums do not fill its image (a bug in glint)"))?;
        let attributes = file.attributes.into_iter().filter(|(k, _)| k != partial::SAMPLES_KEY).collect();
        Ok(Self { film, attributes, ranges: file.ranges })
    }
}

#[pymethods]
impl Partial {
    /// The image of the samples held, (height, width, 3) float32.
    #[getter]
    fn image<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        image_array(py, self.film.width, self.film.height, &self.film.to_rgb())
    }

    /// The sample ranges held, as (a, b) pairs: samples a to b − 1.
    #[getter]
    fn samples(&self) -> Vec<(u32, u32)> {
        self.ranges.clone()
    }

    /// Writes the part in the format the extension names, as `glint merge` writes: `.exr` a
    /// partial EXR (its exact sums and samples, which `glint merge` reads); `.png`, `.pfm`,
    /// `.hdr` the image alone. Other extensions are refused.
    fn save(&self, path: &Bound<'_, PyAny>) -> PyResult<()> {
        let path = path_argument(path)?;
        partial::write_as_named(&path, &self.film, &self.header()).map_err(glint_error)
    }

    fn __getstate__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyBytes>> {
        Ok(PyBytes::new(py, &self.encode()?))
    }

    fn __setstate__(&mut self, state: &[u8]) -> PyResult<()> {
        *self = Partial::from_file(partial::decode(state, Path::new("<pickled part>")).map_err(glint_error)?)?;
        Ok(())
    }

    /// An empty part for unpickling (`__setstate__` fills it).
    #[new]
    fn empty() -> Self {
        Self { film: Film::new(0, 0), attributes: Vec::new(), ranges: Vec::new() }
    }

    fn __repr__(&self) -> String {
        format!("Partial({}x{}, samples {})", self.film.width, self.film.height, partial::format_ranges(&self.ranges))
    }
}

/// Loads a scene file (.toml, .json, or a Mitsuba .xml; a str, bytes or path-like path);
/// `params` set a Mitsuba scene's `<default>`s, as `-D name=value` does.
#[pyfunction]
#[pyo3(signature = (path, **params))]
fn load_file(py: Python<'_>, path: &Bound<'_, PyAny>, params: Option<&Bound<'_, PyDict>>) -> PyResult<Scene> {
    let path = path_argument(path)?;
    let mut defines = Vec::new();
    if let Some(params) = params {
        for (k, v) in params.iter() {
            defines.push((k.extract::<String>()?, v.str()?.to_string()));
        }
    }
    read_file(py, path, defines)
}

fn read_file(py: Python<'_>, path: PathBuf, defines: Vec<(String, String)>) -> PyResult<Scene> {
    Scene::load(py, SceneSource::File { path, defines, search_path: Vec::new(), no_default_light: false })
}

/// Loads a scene from a dict with the native format's schema (the TOML file's tables as
/// dicts, its arrays as lists, tuples or numpy arrays, its numbers Python's or numpy's); files
/// it names are found from the working directory. Errors name the key path
/// (`shapes[0].radius`).
#[pyfunction]
fn load_dict(py: Python<'_>, description: &Bound<'_, PyDict>) -> PyResult<Scene> {
    let directory = std::env::current_dir().map_err(glint_error)?;
    read_dict(py, description.as_any(), directory)
}

fn read_dict(py: Python<'_>, description: &Bound<'_, PyAny>, directory: PathBuf) -> PyResult<Scene> {
    let json = describe(description, "", 0)?.to_json().map_err(glint_error)?;
    Scene::load(py, SceneSource::Description { json, directory })
}

/// A Python value as a scene description: dicts with str keys, lists and tuples, str, int,
/// float, bool, None, path-like objects (as their str) and numpy arrays and scalars (as
/// their `tolist()`).
fn describe(value: &Bound<'_, PyAny>, path: &str, depth: usize) -> PyResult<Description> {
    let refuse = |message: String| glint_error(DescriptionError::new(path, message));
    if depth > description::MAX_DEPTH {
        return Err(refuse(format!(
            "nested more than {} levels deep (a dict or list that contains itself?)",
            description::MAX_DEPTH
        )));
    }
    if value.is_none() {
        return Ok(Description::Null);
    }
    if let Ok(b) = value.downcast::<PyBool>() {
        return Ok(Description::Bool(b.is_true()));
    }
    if value.is_instance_of::<PyInt>() {
        return match value.extract::<i128>() {
            Ok(i) => Ok(Description::Integer(i)),
            Err(_) => Err(refuse(format!("{} is too large a number", value.str()?))),
        };
    }
    if let Ok(f) = value.downcast::<PyFloat>() {
        return Ok(Description::Float(f.value()));
    }
    if let Ok(s) = value.downcast::<PyString>() {
        return Ok(Description::Text(s.to_str().map_err(|e| refuse(e.to_string()))?.to_string()));
    }
    if let Ok(d) = value.downcast::<PyDict>() {
        let mut entries = Vec::with_capacity(d.len());
        for (k, v) in d.iter() {
            let Ok(key) = k.downcast::<PyString>() else {
                let kind = k.get_type().name()?.to_string();
                return Err(refuse(format!("the key {} is of type `{kind}`: keys must be strings", k.repr()?)));
            };
            let key = key.to_str().map_err(|e| refuse(e.to_string()))?.to_string();
            let item = describe(&v, &description::key_path(path, &key), depth + 1)?;
            entries.push((key, item));
        }
        return Ok(Description::Table(entries));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let mut items = Vec::new();
        for (k, item) in value.try_iter()?.enumerate() {
            items.push(describe(&item?, &description::index_path(path, k), depth + 1)?);
        }
        return Ok(Description::List(items));
    }
    if value.hasattr("__fspath__")? {
        return describe(&value.py().import("os")?.call_method1("fsdecode", (value,))?, path, depth + 1);
    }
    if value.hasattr("tolist")? {
        return describe(&value.call_method0("tolist")?, path, depth + 1);
    }
    let kind = value.get_type().name()?.to_string();
    Err(refuse(format!(
        "a value of type `{kind}`, which a scene description cannot hold (a dict, list, tuple, str, number, bool, None or numpy array)"
    )))
}

/// Reads a pickled scene again (`Scene.__reduce__`): `origin` "file" (`place` the path,
/// `params` its parameters) or "dict" (`place` the directory its files are found from, `json`
/// the description).
#[pyfunction]
#[pyo3(name = "_restore_scene")]
fn restore_scene(
    py: Python<'_>,
    origin: &str,
    place: PathBuf,
    params: Vec<(String, String)>,
    json: Option<String>,
    fingerprint: u64,
) -> PyResult<Scene> {
    let scene = match (origin, json) {
        ("file", _) => read_file(py, place.clone(), params)?,
        ("dict", Some(json)) => {
            let description = py.import("json")?.call_method1("loads", (json,))?;
            read_dict(py, &description, place.clone())?
        }
        _ => return Err(glint_error(format!("a pickled scene of an unknown origin `{origin}`"))),
    };
    if scene.source_fingerprint != fingerprint {
        return Err(glint_error(format!(
            "the scene's files changed since it was pickled (read again from `{}`): a render of it would not be the pickled scene's",
            place.display()
        )));
    }
    Ok(scene)
}

/// Refuses, before any work, an output that cannot be written or whose extension names no
/// image format (`python -m glint.distributed -o`).
#[pyfunction]
#[pyo3(name = "_check_output")]
fn check_output(path: &Bound<'_, PyAny>) -> PyResult<()> {
    glint_cli::output::check_writable(&path_argument(path)?).map(|_| ()).map_err(glint_error)
}

/// Parts of one render (from `render(samples=…)` or earlier merges) added into the part that
/// holds all their samples: bit for bit the render of their union. Parts of other renders or
/// sharing samples are refused.
#[pyfunction]
fn merge(parts: Vec<PyRef<'_, Partial>>) -> PyResult<Partial> {
    let files = parts
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let bytes = p.encode()?;
            partial::decode(&bytes, Path::new(&format!("part {k}"))).map_err(glint_error)
        })
        .collect::<PyResult<Vec<_>>>()?;
    let merged = partial::merge(files).map_err(glint_error)?;
    let attributes = merged.attributes.into_iter().filter(|(k, _)| k != partial::SAMPLES_KEY).collect();
    Ok(Partial { film: merged.film, attributes, ranges: merged.ranges })
}

/// Reads a part written by `Partial.save` or `glint render --samples A..B` (a partial EXR),
/// to merge with others.
#[pyfunction]
fn load_partial(path: &Bound<'_, PyAny>) -> PyResult<Partial> {
    Partial::from_file(partial::read(&path_argument(path)?).map_err(glint_error)?)
}

/// An image argument: a path, or a (height, width, 3) array.
fn image_argument(value: &Bound<'_, PyAny>, what: &str) -> PyResult<judge::Image> {
    if value.is_instance_of::<PyString>() || value.is_instance_of::<PyBytes>() || value.hasattr("__fspath__")? {
        return judge::read_image(&path_argument(value)?).map_err(glint_error);
    }
    let not_an_image = |_| PyValueError::new_err(format!("{what}: expected a path or a numpy array"));
    let array: PyReadonlyArrayDyn<'_, f32> =
        value.call_method1("astype", ("float32",)).map_err(not_an_image)?.extract().map_err(not_an_image)?;
    let shape = array.shape().to_vec();
    if shape.len() != 3 || shape[2] != 3 {
        return Err(PyValueError::new_err(format!("{what}: expected shape (height, width, 3), got {shape:?}")));
    }
    let values = array
        .as_slice()
        .map(<[f32]>::to_vec)
        .or_else(|_| Ok::<_, PyErr>(array.as_array().iter().copied().collect()))?;
    let pixels = values.chunks_exact(3).map(|c| Rgb::new(c[0], c[1], c[2])).collect();
    Ok(judge::Image { width: shape[1] as u32, height: shape[0] as u32, pixels, attributes: Default::default() })
}

/// Compares `image` with `reference` (paths or arrays): MSE, relMSE, MAE and the ratio of
/// means per channel, LDR-ꟻLIP's mean, and with `variance` (the reference's per-sample
/// variance) and `spp` the per-pixel Z-test, as `glint compare` computes them.
#[pyfunction]
#[pyo3(signature = (image, reference, variance=None, spp=None, exposure=None))]
fn compare<'py>(
    py: Python<'py>,
    image: &Bound<'py, PyAny>,
    reference: &Bound<'py, PyAny>,
    variance: Option<&Bound<'py, PyAny>>,
    spp: Option<u64>,
    exposure: Option<f32>,
) -> PyResult<Bound<'py, PyDict>> {
    // What the warnings call each image: its path, or what the argument was.
    let name =
        |value: &Bound<'py, PyAny>, what: &str| value.extract::<PathBuf>().unwrap_or_else(|_| PathBuf::from(what));
    let (image_name, reference_name) = (name(image, "the image array"), name(reference, "the reference array"));
    let (image, reference) = (image_argument(image, "image")?, image_argument(reference, "reference")?);
    warn_all(py, &judge::warnings(&image_name, &image, &reference_name, &reference))?;
    let metrics = judge::metrics(&image, &reference).map_err(PyValueError::new_err)?;
    let flip = match exposure {
        Some(exposure) => judge::flip(&image, &reference, exposure),
        None => judge::hdr_flip(&image, &reference),
    }
    .map_err(PyValueError::new_err)?;
    let d = PyDict::new(py);
    d.set_item("mse", metrics.mse.to_vec())?;
    d.set_item("rel_mse", metrics.rel_mse.to_vec())?;
    d.set_item("mae", metrics.mae.to_vec())?;
    d.set_item("mean_ratio", metrics.mean_ratio.to_vec())?;
    d.set_item("flip", flip.mean)?;
    let non_finite = PyDict::new(py);
    non_finite.set_item("image", metrics.non_finite.image)?;
    non_finite.set_item("reference", metrics.non_finite.reference)?;
    non_finite.set_item("left_out", metrics.non_finite.either)?;
    d.set_item("non_finite_pixels", non_finite)?;
    match (variance, spp) {
        (Some(variance), Some(spp)) => {
            let variance = image_argument(variance, "variance")?;
            let z = judge::z_test(&image, &reference, &variance, spp).map_err(PyValueError::new_err)?;
            let t = PyDict::new(py);
            t.set_item("fraction_passed", z.fraction)?;
            t.set_item("passed", z.passed)?;
            t.set_item("alpha", z.alpha)?;
            d.set_item("z_test", t)?;
        }
        (None, None) => d.set_item("z_test", py.None())?,
        _ => return Err(PyValueError::new_err("the Z-test needs both variance and spp")),
    }
    Ok(d)
}

#[pymodule]
fn _glint(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Scene>()?;
    m.add_class::<Partial>()?;
    m.add_function(wrap_pyfunction!(load_file, m)?)?;
    m.add_function(wrap_pyfunction!(load_dict, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_function(wrap_pyfunction!(load_partial, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(restore_scene, m)?)?;
    m.add_function(wrap_pyfunction!(check_output, m)?)?;
    m.add("GlintError", m.py().get_type::<GlintError>())?;
    m.add("GlintWarning", m.py().get_type::<GlintWarning>())?;
    Ok(())
}
