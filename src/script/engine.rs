//! The sandboxed Rhai engine: the language's core packages without clocks, sleeping or
//! module loading, and limits on everything a script could grow without bound.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use rhai::debugger::{DebuggerCommand, DebuggerEvent};
use rhai::module_resolvers::DummyModuleResolver;
use rhai::packages::{
    BasicArrayPackage, BasicMapPackage, BasicMathPackage, BitFieldPackage, CorePackage, LogicPackage,
    MoreStringPackage, Package,
};
use rhai::{ASTNode, Dynamic, Engine, OptimizationLevel, Position, FLOAT, INT};

use super::api::convert::{error, ScriptResult};

/// What a script may use. The defaults leave room for any animation script and stop a
/// runaway one within a second or two.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Limits {
    /// Operations per host call (`setup`, one `frame`, `sweep`), including the top level.
    pub max_operations: u64,
    /// Nested function calls.
    pub max_call_levels: usize,
    /// Expression nesting at the top level.
    pub max_expr_depth: usize,
    /// Expression nesting inside functions.
    pub max_function_expr_depth: usize,
    /// Bytes in one string.
    pub max_string_size: usize,
    /// Elements in one array.
    pub max_array_size: usize,
    /// Entries in one object map.
    pub max_map_size: usize,
    /// Variables alive at once.
    pub max_variables: usize,
    /// Functions a script may define.
    pub max_functions: usize,
    /// Wall-clock time per host call.
    pub time_limit: Duration,
}

impl Default for Limits {
    fn default() -> Self {
        Self {
            max_operations: 5_000_000,
            max_call_levels: 48,
            max_expr_depth: 64,
            max_function_expr_depth: 48,
            max_string_size: 64 * 1024,
            max_array_size: 100_000,
            max_map_size: 10_000,
            max_variables: 10_000,
            max_functions: 512,
            time_limit: Duration::from_secs(30),
        }
    }
}

/// What the engine's callbacks watch during a host call: the wall-clock deadline, the
/// position of the statement being run, and whether `print` and `debug` output is shown.
///
/// Rhai reports a broken limit at the outermost call, not where it happened (it unwinds
/// limit errors through every call level), so the engine's debugger hook records each
/// statement's position as it starts and the error is located there instead.
#[derive(Debug, Clone)]
pub struct Watch {
    origin: Instant,
    /// Deadline in nanoseconds since `origin`; `u64::MAX` when no call is running.
    deadline: Arc<AtomicU64>,
    limit: Duration,
    /// Line (high 32 bits) and column of the statement running; 0 before the first.
    statement: Arc<AtomicU64>,
    /// `print` and `debug` output is dropped (frames replayed only to reach a later one).
    muted: Arc<AtomicBool>,
}

impl Watch {
    fn new(limit: Duration) -> Self {
        Self {
            origin: Instant::now(),
            deadline: Arc::new(AtomicU64::new(u64::MAX)),
            limit,
            statement: Arc::new(AtomicU64::new(0)),
            muted: Arc::new(AtomicBool::new(false)),
        }
    }

    /// Drops (`true`) or shows (`false`) the script's `print` and `debug` output from now on.
    pub fn mute(&self, muted: bool) {
        self.muted.store(muted, Ordering::Relaxed);
    }

    fn muted(&self) -> bool {
        self.muted.load(Ordering::Relaxed)
    }

    /// Starts watching a host call: its clock and its statements.
    pub fn start(&self) {
        let at = self.origin.elapsed().saturating_add(self.limit).as_nanos();
        self.deadline.store(u64::try_from(at).unwrap_or(u64::MAX), Ordering::Relaxed);
        self.statement.store(0, Ordering::Relaxed);
    }

    fn passed(&self) -> bool {
        self.origin.elapsed().as_nanos() > self.deadline.load(Ordering::Relaxed) as u128
    }

    fn enter(&self, position: Position) {
        if let (Some(line), Some(column)) = (position.line(), position.position()) {
            self.statement.store(((line as u64) << 32) | column as u64, Ordering::Relaxed);
        }
    }

    /// The position of the statement that was running last, if any ran.
    pub fn statement(&self) -> Position {
        match self.statement.load(Ordering::Relaxed) {
            0 => Position::NONE,
            v => Position::new((v >> 32) as u16, (v & 0xffff_ffff) as u16),
        }
    }
}

/// Replaces the math package's transcendental functions with `libm`'s (musl's, in Rust), which
/// give the same bits on every CPU. The package calls the system's libm, and glibc picks its
/// implementation per CPU at load time: with and without FMA, `sin`, `cos` and `exp` differ in
/// the last bit on 0.07 % of arguments in [−π, π], so a script's motion, and the frames of a
/// sequence split across a cluster of mixed CPUs, would too. Functions registered on the
/// engine take precedence over packages. (`sqrt`, the rounding functions and the conversions
/// are exact in IEEE arithmetic and stay as they are.) The power operator `**` (and `**=`) on
/// floats, and on an integer raised to a float, is `libm::pow` too: Rhai's built-in calls the
/// system's `powf`, so its fast-operators mode, which ignores registered operators for
/// built-in types, is turned off (integer powers stay exact and built in).
fn deterministic_math(engine: &mut Engine) {
    type Unary = fn(FLOAT) -> FLOAT;
    let unary: [(&str, Unary); 15] = [
        ("sin", libm::sin),
        ("cos", libm::cos),
        ("tan", libm::tan),
        ("sinh", libm::sinh),
        ("cosh", libm::cosh),
        ("tanh", libm::tanh),
        ("asin", libm::asin),
        ("acos", libm::acos),
        ("atan", libm::atan),
        ("asinh", libm::asinh),
        ("acosh", libm::acosh),
        ("atanh", libm::atanh),
        ("exp", libm::exp),
        ("ln", libm::log),
        ("log", libm::log10),
    ];
    for (name, f) in unary {
        engine.register_fn(name, f);
    }
    engine.register_fn("atan", libm::atan2);
    engine.register_fn("hypot", libm::hypot);
    engine.register_fn("log", |x: FLOAT, base: FLOAT| libm::log(x) / libm::log(base));
    engine.set_fast_operators(false);
    engine.register_fn("**", libm::pow);
    engine.register_fn("**", |x: FLOAT, y: INT| libm::pow(x, y as FLOAT));
    engine.register_fn("**", |x: INT, y: FLOAT| libm::pow(x as FLOAT, y));
    engine.register_fn("**=", |x: &mut FLOAT, y: FLOAT| *x = libm::pow(*x, y));
    engine.register_fn("**=", |x: &mut FLOAT, y: INT| *x = libm::pow(*x, y as FLOAT));
}

/// How often (in operations) the progress callback looks at the clock.
const CLOCK_EVERY: u64 = 1 << 14;

/// A sandboxed engine with `limits`; `file` names the script in `print` and `debug` output,
/// which goes to standard error unless the returned [`Watch`] is muted.
pub fn sandboxed(limits: &Limits, file: &str) -> (Engine, Watch) {
    let mut engine = Engine::new_raw();
    // The standard library minus the time package (clocks make frames irreproducible) and
    // blobs (no use here).
    CorePackage::new().register_into_engine(&mut engine);
    BitFieldPackage::new().register_into_engine(&mut engine);
    LogicPackage::new().register_into_engine(&mut engine);
    BasicMathPackage::new().register_into_engine(&mut engine);
    deterministic_math(&mut engine);
    BasicArrayPackage::new().register_into_engine(&mut engine);
    BasicMapPackage::new().register_into_engine(&mut engine);
    MoreStringPackage::new().register_into_engine(&mut engine);
    engine.set_optimization_level(OptimizationLevel::Simple);

    engine.set_max_operations(limits.max_operations);
    engine.set_max_call_levels(limits.max_call_levels);
    engine.set_max_expr_depths(limits.max_expr_depth, limits.max_function_expr_depth);
    engine.set_max_string_size(limits.max_string_size);
    engine.set_max_array_size(limits.max_array_size);
    engine.set_max_map_size(limits.max_map_size);
    engine.set_max_variables(limits.max_variables);
    engine.set_max_functions(limits.max_functions);

    // No files: `import` finds nothing, `eval` is off; `sleep` would stall past the progress
    // callback's clock.
    engine.set_module_resolver(DummyModuleResolver::new());
    engine.disable_symbol("eval");
    engine.register_fn("sleep", |_: INT| -> ScriptResult<()> { error("sleep is not available in scripts") });
    engine
        .register_fn("sleep", |_: FLOAT| -> ScriptResult<()> { error("sleep is not available in scripts") });

    let watch = Watch::new(limits.time_limit);
    let clock = watch.clone();
    engine.on_progress(move |ops| match ops % CLOCK_EVERY == 0 && clock.passed() {
        true => Some(Dynamic::from("time limit")),
        false => None,
    });
    let statements = watch.clone();
    // The debugger interface is marked volatile, not deprecated.
    #[allow(deprecated)]
    engine.register_debugger(
        |_, debugger| debugger,
        move |_, event, node, _, position| {
            if let (DebuggerEvent::Step, ASTNode::Stmt(_)) = (event, node) {
                statements.enter(position);
            }
            Ok(DebuggerCommand::StepInto)
        },
    );
    let name = file.to_owned();
    let output = watch.clone();
    engine.on_print(move |text| {
        if !output.muted() {
            eprintln!("{name}: {text}");
        }
    });
    let name = file.to_owned();
    let output = watch.clone();
    engine.on_debug(move |text, _, pos| match (output.muted(), pos.line(), pos.position()) {
        (true, ..) => {}
        (false, Some(line), Some(column)) => eprintln!("{name}:{line}:{column}: {text}"),
        (false, ..) => eprintln!("{name}: {text}"),
    });
    (engine, watch)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rhai::{Array, Scope};

    /// A script's transcendental functions and float powers (`**`, `**=`, constant or not) are
    /// `libm`'s, bit for bit, on arguments where glibc's differ from them (so the package's
    /// functions and Rhai's built-in `**`, had they stayed, would fail this on glibc: its `pow`
    /// differs from `libm`'s on 8 % of these arguments).
    #[test]
    fn a_scripts_math_is_libm_bit_for_bit() {
        let (engine, _) = sandboxed(&Limits::default(), "math.rhai");
        let xs: Vec<FLOAT> = (0..2000).map(|i| -6.0 + FLOAT::from(i) * 0.006_017).collect();
        let mut scope = Scope::new();
        scope.push("xs", xs.iter().map(|&x| Dynamic::from_float(x)).collect::<Array>());
        let script = "let out = []; for x in xs { let a = x * x + 0.5; let u = x / 7.0; \
            let p = a; p **= 1.37; let q = a; q **= 3; \
            out.append([sin(x), cos(x), tan(x), sinh(x), cosh(x), tanh(x), asin(u), acos(u), \
            atan(x), asinh(x), acosh(a + 1.0), atanh(u), exp(x), ln(a), log(a), atan(x, 0.7), \
            hypot(x, 0.3), log(a, 3.0), a ** u, a ** 3, 2 ** u, p, q, 1.7 ** 0.3]); } out";
        let got: Array = engine.eval_with_scope(&mut scope, script).unwrap();
        let (mut system_differs, mut pow_differs) = (false, false);
        for (k, &x) in xs.iter().enumerate() {
            let (a, u) = (x * x + 0.5, x / 7.0);
            let want = [
                libm::sin(x),
                libm::cos(x),
                libm::tan(x),
                libm::sinh(x),
                libm::cosh(x),
                libm::tanh(x),
                libm::asin(u),
                libm::acos(u),
                libm::atan(x),
                libm::asinh(x),
                libm::acosh(a + 1.0),
                libm::atanh(u),
                libm::exp(x),
                libm::log(a),
                libm::log10(a),
                libm::atan2(x, 0.7),
                libm::hypot(x, 0.3),
                libm::log(a) / libm::log(3.0),
                libm::pow(a, u),
                libm::pow(a, 3.0),
                libm::pow(2.0, u),
                libm::pow(a, 1.37),
                libm::pow(a, 3.0),
                libm::pow(1.7, 0.3),
            ];
            for (j, w) in want.iter().enumerate() {
                let g = got[k * want.len() + j].as_float().unwrap();
                assert_eq!(g.to_bits(), w.to_bits(), "function {j} of the script at {x}: {g} against {w}");
            }
            system_differs |= x.sin() != libm::sin(x) || x.cos() != libm::cos(x) || x.exp() != libm::exp(x);
            pow_differs |= (x * x + 0.5).powf(x / 7.0) != libm::pow(x * x + 0.5, x / 7.0);
        }
        // Where the system's libm is glibc (CI's), it differs from musl's on some of these
        // arguments, so the test would catch the package's functions. A musl system's agree.
        if cfg!(target_env = "gnu") {
            assert!(
                system_differs,
                "glibc's sin, cos and exp agree with libm's here: the test proves nothing"
            );
            assert!(pow_differs, "glibc's pow agrees with libm's here: the test proves nothing about **");
        }
    }
}
