//! N steps of one method on one system from one of its presets, nothing else: the tool for
//! ns/step by process (`bench/formula_ratio.py`, `bench/general_ratio.py`,
//! `bench/sleigh_ratio.py`, `perf stat`), and what `bench/fast_path_instructions.sh` counts
//! under callgrind (instructions per step are the difference between two step counts, so that
//! setting up and exiting cancel).
//!
//! `step_loop SYSTEM METHOD PATH STEPS [PRESET [RESTART]]`: METHOD is an index into
//! `Method::all()` (the paper's five, then the others) or an id with its parameters
//! (`spark:stages=4`), PRESET an index into the system's
//! presets (0 if left out); RESTART, if given and not 0, starts again from the preset's start
//! every RESTART steps (a scene whose motion runs away, as the inclined sleigh's, is then
//! measured as its scene runs, not as its far future).
//! PATH, on a system of the paper's class: `fast` (the method's default), `general` (its
//! general Newton path in the class), `formulas` (the default path on the system given as
//! formulas, `FormulaSpec::of`), `as-general` (the method's general-class step on the system
//! seen through `General`), `general-formulas` (the general-class step on the system's
//! general form compiled with `detect_class: false`). On a built-in of the general class
//! (`chaplygin_sleigh`): `fast` (the built-in) or `formulas` (its general form compiled).
//! `step_loop list` prints the indices and which methods have a general path.

use nhlab_core::model::custom::Custom;
use nhlab_core::model::custom::{GeneralCustom, Structure};
use nhlab_core::model::mechanical::{General, GeneralBuiltIn, Mechanical};
use nhlab_core::{BuiltIn, CustomLimits, CustomSystem, FormulaSpec, GeneralSpec, Preset, System};
use nhlab_core::{
    Method, MethodSpec, State, SystemInfo, Vector, for_each_general_system, for_each_system,
};

/// What runs: the method, on which path, the preset, the steps.
struct Run {
    method: Method,
    path: String,
    preset: usize,
    steps: u64,
    restart: u64,
}

impl Run {
    /// The lengths of the runs from the start that make up the steps.
    fn runs(&self) -> impl Iterator<Item = u64> {
        let each = if self.restart == 0 { self.steps.max(1) } else { self.restart };
        let (whole, rest) = (self.steps / each, self.steps % each);
        std::iter::repeat_n(each, whole as usize).chain((rest > 0).then_some(rest))
    }
}

/// The preset asked for, or exits saying how many there are.
fn preset<'a>(info: &'a SystemInfo, run: &Run) -> &'a Preset {
    info.presets.get(run.preset).unwrap_or_else(|| {
        eprintln!("{} has {} presets, numbered from 0", info.id, info.presets.len());
        std::process::exit(2);
    })
}

/// The built-in's general form at the preset's parameters, compiled on the general path.
fn general_formulas<const N: usize, const R: usize>(
    info: &SystemInfo,
    p: &Preset,
) -> GeneralCustom<N, R> {
    let spec = GeneralSpec::of_built_in(info, &info.preset_params(p)).expect("a general form");
    let spec = GeneralSpec { detect_class: false, ..spec };
    let compiled = CustomSystem::compile_general(&spec, &[], &CustomLimits::default())
        .expect("a built-in's general form compiles");
    let Structure::General(compiled) = compiled.structure else { unreachable!("class not sought") };
    GeneralCustom::new(compiled)
}

fn run<S: BuiltIn<N, R>, const N: usize, const R: usize>(system: &str, run: &Run) {
    let info = S::info();
    if info.id != system {
        return;
    }
    let p = preset(info, run);
    let sys = S::new(&info.preset_params(p));
    match run.path.as_str() {
        "formulas" => {
            let overrides: Vec<_> = p.params.iter().map(|(n, v)| (n.to_string(), *v)).collect();
            let spec = FormulaSpec::of(info).expect("a class built-in");
            let compiled = CustomSystem::compile(&spec, &overrides, &CustomLimits::default())
                .expect("a built-in's formula form compiles");
            let class = compiled.class_compiled().expect("the class").clone();
            steps_on(&Custom::<N, R>::new(class), p, run);
        }
        "as-general" => general_steps_on(&General(&sys), p, run),
        "general-formulas" => general_steps_on(&general_formulas::<N, R>(info, p), p, run),
        _ => steps_on(&sys, p, run),
    }
}

fn run_general<S: GeneralBuiltIn<N, R>, const N: usize, const R: usize>(system: &str, run: &Run) {
    let info = S::info();
    if info.id != system {
        return;
    }
    let p = preset(info, run);
    match run.path.as_str() {
        "fast" => general_steps_on(&S::new(&info.preset_params(p)), p, run),
        "formulas" => general_steps_on(&general_formulas::<N, R>(info, p), p, run),
        other => {
            eprintln!("{system} is of the general class: PATH is fast or formulas, not {other}");
            std::process::exit(2);
        }
    }
}

/// The end point, and the Newton iterations per step (implicit methods).
fn report<const N: usize>(run: &Run, p: &Preset, q: &Vector<N>) {
    let per_step = nhlab_core::solver::newton::take_iterations() as f64 / run.steps as f64;
    println!(
        "{} on {}: q = {:?}, {per_step:.2} Newton iterations per step",
        run.method.label(),
        p.id,
        q.as_slice()
    );
}

fn steps_on<S: System<N, R>, const N: usize, const R: usize>(sys: &S, p: &Preset, run: &Run) {
    let (q, v) = (Vector::<N>::from_column_slice(p.q), Vector::<N>::from_column_slice(p.v));
    let start = State::with_continuous_multiplier(sys, q, v).expect("a preset is regular");
    let mut st = start;
    for n in run.runs() {
        st = start;
        run.method.steps(sys, &mut st, p.step, n).expect("the preset runs");
    }
    report(run, p, &st.q);
}

fn general_steps_on<S: Mechanical<N, R>, const N: usize, const R: usize>(
    sys: &S,
    p: &Preset,
    run: &Run,
) {
    let (q, v) = (Vector::<N>::from_column_slice(p.q), Vector::<N>::from_column_slice(p.v));
    let start = State::general_start(sys, q, v).expect("a preset is regular");
    let mut st = start;
    for n in run.runs() {
        st = start;
        run.method.steps_general(sys, &mut st, p.step, n).expect("the preset runs");
    }
    report(run, p, &st.q);
}

/// A method named by id and parameters: `spark:stages=4`, `dla:alpha=0.3`.
fn spec(text: &str) -> Result<Method, Box<dyn std::error::Error>> {
    let (id, params) = text.split_once(':').unwrap_or((text, ""));
    let mut spec = MethodSpec::new(id);
    for pair in params.split(',').filter(|p| !p.is_empty()) {
        let (name, value) = pair.split_once('=').ok_or("a parameter is NAME=VALUE")?;
        spec = spec.with(name, value.parse()?);
    }
    Ok(Method::from_spec(&spec)?)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let all = Method::all();
    if args.first().map(String::as_str) == Some("list") {
        for (i, m) in all.iter().enumerate() {
            println!("{i} {} {}", m.label().replace(' ', "_"), m.general_path().is_some());
        }
        return Ok(());
    }
    let (system, method, path, steps, preset, restart) = match args.as_slice() {
        [s, m, p, n] => (s, m, p, n, "0", "0"),
        [s, m, p, n, preset] => (s, m, p, n, preset.as_str(), "0"),
        [s, m, p, n, preset, restart] => (s, m, p, n, preset.as_str(), restart.as_str()),
        _ => {
            return Err("usage: step_loop SYSTEM METHOD PATH STEPS [PRESET [RESTART]] | \
                        step_loop list"
                .into());
        }
    };
    let m = match method.parse::<usize>() {
        Ok(i) => *all.get(i).ok_or("no such method index")?,
        Err(_) => spec(method)?,
    };
    let method = match path.as_str() {
        "fast" | "formulas" | "as-general" | "general-formulas" => m,
        "general" => m.general_path().ok_or("this method has no general path")?,
        _ => return Err("PATH is fast, general, formulas, as-general or general-formulas".into()),
    };
    if method.info().class_only.is_some() && path.contains("general") && path != "general" {
        return Err(format!("{} has no general-class step", method.label()).into());
    }
    let r = Run {
        method,
        path: path.clone(),
        preset: preset.parse()?,
        steps: steps.parse()?,
        restart: restart.parse()?,
    };
    for_each_system!(run, system, &r);
    for_each_general_system!(run_general, system, &r);
    Ok(())
}
