//! A compiled [`Script`] attached to a scene World: each call into the script lends it the
//! World ([`super::lent`]), whose components its API reads and writes in place.
//!
//! The host calls `setup()` once and `frame(t)` per frame. Before each call the script's top
//! level runs again (Rhai functions see no outer variables; top-level `const`s are read inside
//! functions as `global::NAME`), so a frame depends only on the World and `t`, never on
//! script variables left over from earlier frames.

use std::path::Path;
use std::sync::Arc;

use bevy_ecs::prelude::{Entity, IntoScheduleConfigs, World};
use rhai::{Array, CallFnOptions, Dynamic, Engine, FuncArgs, Map, Scope, AST};

use super::api;
use super::engine::{sandboxed, Limits, Watch};
use super::error::{ErrorKind, ScriptError};
use super::lent::{follow_focus, prepare, Clock, LentWorld, Written};
use super::shutter::{apply_shutter_pose, ClosePose, Saved, ShutterPose};
use crate::scene::{fields, spawn_world, SceneDesc};
use crate::store::{PrimitiveStore, SoaStore};
use crate::trace::TraceScene;
use crate::world::components::{MaterialRef, Name};
use crate::world::resources::{CameraRig, Materials, SceneSettings};
use crate::world::SceneWorld;

/// A parsed script, ready to attach to any number of Worlds.
#[derive(Clone)]
pub struct Script {
    file: String,
    source: Arc<str>,
    ast: AST,
    limits: Limits,
}

impl Script {
    /// Reads and compiles the script at `path`.
    pub fn load(path: &Path, limits: Limits) -> Result<Self, ScriptError> {
        let file = path.display().to_string();
        let source = std::fs::read_to_string(path)
            .map_err(|e| ScriptError::new(&file, ErrorKind::Read, e.to_string()))?;
        Self::from_source(&file, &source, limits)
    }

    /// Compiles `source`; `file` names it in errors.
    pub fn from_source(file: &str, source: &str, limits: Limits) -> Result<Self, ScriptError> {
        let (engine, _) = sandboxed(&limits, file);
        let ast =
            engine.compile(source).map_err(|e| ScriptError::from_parse_of(file, &e, &limits, source))?;
        Ok(Self { file: file.to_owned(), source: source.into(), ast, limits })
    }

    /// The file name errors use.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// The script's text (hashed into frame metadata).
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The sandbox limits.
    pub fn limits(&self) -> &Limits {
        &self.limits
    }

    /// True when the script defines `fn name` with `arity` parameters.
    pub fn defines(&self, name: &str, arity: usize) -> bool {
        self.ast.iter_functions().any(|f| f.name == name && f.params.len() == arity)
    }

    /// An error unless the script defines `fn name` with `arity` parameters.
    pub fn require(&self, name: &str, arity: usize, purpose: &str) -> Result<(), ScriptError> {
        match self.defines(name, arity) {
            true => Ok(()),
            false => {
                let params = ["", "t", "a, b"][arity.min(2)];
                let message = format!("the script defines no `fn {name}({params})`, which {purpose}");
                Err(ScriptError::new(&self.file, ErrorKind::MissingFunction, message))
            }
        }
    }
}

/// The engine and script of a World.
pub struct ScriptRuntime {
    engine: Engine,
    script: Script,
    watch: Watch,
    lent: LentWorld,
}

impl ScriptRuntime {
    /// Calls `fn name(args)`, the top level first, under the sandbox's limits, with `world`
    /// lent to the script (`quiet`: its writes are to be undone).
    fn call(
        &self,
        world: &mut World,
        quiet: bool,
        name: &str,
        args: impl FuncArgs,
        context: &str,
    ) -> Result<Dynamic, ScriptError> {
        let (result, written) = self.lent.lend(world, quiet, || {
            self.watch.start();
            let options = CallFnOptions::new().eval_ast(true).rewind_scope(true);
            self.engine.call_fn_with_options::<Dynamic>(
                options,
                &mut Scope::new(),
                &self.script.ast,
                name,
                args,
            )
        });
        let result = result.map_err(|e| self.error(&e).in_call(context))?;
        self.check(world, &written, context)?;
        Ok(result)
    }

    /// Runs the script's top level alone, with `world` lent.
    fn run_top_level(&self, world: &mut World) -> Result<(), ScriptError> {
        let (result, written) = self.lent.lend(world, false, || {
            self.watch.start();
            self.engine.run_ast_with_scope(&mut Scope::new(), &self.script.ast)
        });
        result.map_err(|e| self.error(&e).in_call("the top level"))?;
        self.check(world, &written, "the top level")
    }

    /// Runs a statement of the host's with `value` in scope (sweep parameters), with `world`
    /// lent.
    fn run_with_value(
        &self,
        world: &mut World,
        code: &str,
        value: Dynamic,
    ) -> (Result<(), Box<rhai::EvalAltResult>>, Written) {
        self.lent.lend(world, false, || {
            self.watch.start();
            let mut scope = Scope::new();
            scope.push("value", value);
            self.engine.run_with_scope(&mut scope, code)
        })
    }

    fn error(&self, e: &rhai::EvalAltResult) -> ScriptError {
        ScriptError::from_eval(&self.script.file, e, &self.script.limits, self.watch.statement())
    }

    /// The rules that span several fields (camera pose, `kr + kt`), checked once a call has
    /// made all its writes.
    fn check(&self, world: &World, written: &Written, context: &str) -> Result<(), ScriptError> {
        let fail = |message: String| {
            Err(ScriptError::new(&self.script.file, ErrorKind::Runtime, message).in_call(context))
        };
        if written.camera {
            let rig = world.resource::<CameraRig>();
            if let Err((field, rule)) = fields::view(rig.position, rig.look_at, rig.up) {
                return fail(format!("camera.{field}: {rule}"));
            }
        }
        for &entity in &written.materials {
            let Some(m) = world.get::<MaterialRef>(entity) else { continue };
            let Some(m) = world.resource::<Materials>().table.get(m.0 .0 as usize) else { continue };
            if let Err(rule) = fields::kr_plus_kt(m.kr, m.kt) {
                let name = world.get::<Name>(entity).map_or("?", |n| n.as_str());
                return fail(format!("entity `{name}`: kt: {rule}"));
            }
        }
        Ok(())
    }
}

/// A scene World driven by a script.
pub struct ScriptedWorld<S: PrimitiveStore + 'static = SoaStore> {
    world: SceneWorld<S>,
    runtime: ScriptRuntime,
}

impl<S: PrimitiveStore + 'static> ScriptedWorld<S> {
    /// Spawns `desc` and attaches `script` as [`Self::new`] does; lights read their `colour`
    /// and `intensity` as the scene gives them.
    pub fn from_scene(desc: &SceneDesc, script: &Script) -> Self {
        Self::new(spawn_world::<S>(desc), script)
    }

    /// Attaches `script` to `world`: builds the sandboxed engine with the API over the World,
    /// and adds the systems that follow a focus entity and blur what moves over the shutter.
    /// A light spawned without its [`crate::world::components::LightTerms`] reads as
    /// `colour` = radiance and `intensity` = 1.
    pub fn new(mut world: SceneWorld<S>, script: &Script) -> Self {
        let lent = LentWorld::new(prepare(world.world_mut()));
        let (mut engine, watch) = sandboxed(&script.limits, &script.file);
        api::register(&mut engine, &lent);
        world.world_mut().init_resource::<ShutterPose>();
        world.add_input_system((follow_focus, apply_shutter_pose).chain());
        Self { world, runtime: ScriptRuntime { engine, script: script.clone(), watch, lent } }
    }

    /// Runs `fn setup()` if the script defines it (and the top level either way).
    pub fn setup(&mut self) -> Result<(), ScriptError> {
        let (rt, world) = (&self.runtime, self.world.world_mut());
        match rt.script.defines("setup", 0) {
            true => rt.call(world, false, "setup", (), "setup()").map(|_| ()),
            false => rt.run_top_level(world),
        }
    }

    /// Runs `fn frame(t)` for the frame `clock` describes; the next [`Self::update`] renders
    /// what it wrote.
    pub fn frame(&mut self, clock: Clock) -> Result<(), ScriptError> {
        self.frame_at(clock, false)
    }

    fn frame_at(&mut self, clock: Clock, quiet: bool) -> Result<(), ScriptError> {
        self.runtime.lent.lock().clock = clock;
        let world = self.world.world_mut();
        if world.resource::<SceneSettings>().render.frame != clock.frame {
            world.resource_mut::<SceneSettings>().render.frame = clock.frame;
        }
        let context = format!("frame({}) at frame {}", clock.time, clock.frame);
        self.runtime.call(world, quiet, "frame", (clock.time,), &context).map(|_| ())
    }

    /// Runs `fn frame(t)` for `clock` from the current state, output muted, and undoes it:
    /// returns the pose it reached (at shutter close) and leaves the World, and so the
    /// timeline, as they were, change ticks included.
    pub fn evaluate_at(&mut self, clock: Clock) -> Result<ClosePose, ScriptError> {
        let entities: Vec<Entity> = self.runtime.lent.lock().names.iter().map(|(_, e)| *e).collect();
        let saved = Saved::of(self.world.world(), &entities);
        let before = self.runtime.lent.lock().clock;
        self.mute_output(true);
        let ran = self.frame_at(clock, true);
        self.mute_output(false);
        let reached = ClosePose::of(self.world.world(), &entities);
        saved.restore(self.world.world_mut());
        self.runtime.lent.lock().clock = before;
        ran.map(|()| reached)
    }

    /// The pose at shutter close the next [`Self::update`] blurs towards (from
    /// [`Self::evaluate_at`]), or `None` for a frame without a shutter.
    pub fn set_shutter_pose(&mut self, close: Option<ClosePose>) {
        self.world.world_mut().insert_resource(ShutterPose(close));
    }

    /// The parameter sets `fn sweep()` declares: an array of object maps.
    pub fn sweep_sets(&mut self) -> Result<Vec<Map>, ScriptError> {
        let (rt, world) = (&self.runtime, self.world.world_mut());
        let sets = rt.call(world, false, "sweep", (), "sweep()")?;
        let file = &rt.script.file;
        let fail =
            |message: String| Err(ScriptError::new(file, ErrorKind::Runtime, message).in_call("sweep()"));
        let Some(sets) = sets.try_cast::<Array>() else {
            return fail("sweep() must return an array of object maps, e.g. [#{ aperture: 0.1 }]".into());
        };
        if sets.is_empty() {
            return fail("sweep() returned no parameter sets".into());
        }
        let mut maps = Vec::with_capacity(sets.len());
        for (i, set) in sets.into_iter().enumerate() {
            match set.try_cast::<Map>() {
                Some(map) => maps.push(map),
                None => {
                    return fail(format!("sweep() element {i} is not an object map like #{{ samples: 4 }}"))
                }
            }
        }
        Ok(maps)
    }

    /// Applies one parameter set: through `fn apply(p)` when the script defines it, else
    /// each key as the camera or settings property of that name (`aperture`, `samples`, …).
    pub fn apply(&mut self, params: &Map, index: usize) -> Result<(), ScriptError> {
        let (rt, world) = (&self.runtime, self.world.world_mut());
        let context = format!("parameter set {index}");
        if rt.script.defines("apply", 1) {
            return rt
                .call(world, false, "apply", (Dynamic::from_map(params.clone()),), &context)
                .map(|_| ());
        }
        let mut written = Written::default();
        for (key, value) in params {
            let code = match key.as_str() {
                "focus_on" => "camera.focus_on(value);".to_owned(),
                k if api::scene::CAMERA_PROPERTIES.contains(&k) => format!("camera.{k} = value;"),
                k if api::scene::SETTINGS_PROPERTIES.contains(&k) => format!("settings.{k} = value;"),
                k => {
                    let known =
                        [api::scene::CAMERA_PROPERTIES, api::scene::SETTINGS_PROPERTIES, &["focus_on"]]
                            .concat()
                            .join(", ");
                    let message = format!(
                        "unknown parameter `{k}`; define `fn apply(p)` to use it, or use one of: {known}"
                    );
                    return Err(
                        ScriptError::new(&rt.script.file, ErrorKind::Runtime, message).in_call(context)
                    );
                }
            };
            let (ran, wrote) = rt.run_with_value(world, &code, value.clone());
            ran.map_err(|e| {
                let mut e = rt.error(&e).in_call(format!("{context}, `{key}`"));
                (e.line, e.column) = (None, None);
                e
            })?;
            written.camera |= wrote.camera;
            written.materials.extend(wrote.materials);
        }
        rt.check(world, &written, &context)
    }

    /// Drops (`true`) or shows (`false`) the script's `print` and `debug` output from now on
    /// (shown by default); [`super::Animation`] mutes the frames it replays without rendering.
    pub fn mute_output(&mut self, muted: bool) {
        self.runtime.watch.mute(muted);
    }

    /// Runs the frame schedule over what the script wrote; returns the snapshot.
    pub fn update(&mut self) -> Arc<TraceScene<S>> {
        self.world.update()
    }

    /// The World.
    pub fn world(&self) -> &SceneWorld<S> {
        &self.world
    }

    /// The World, mutably.
    pub fn world_mut(&mut self) -> &mut SceneWorld<S> {
        &mut self.world
    }
}
