//! Moving values between the World and the script's mirror: the mirror taken from a spawned
//! World ([`ScriptState::from_world`]) and the input system that moves the script's writes
//! back ([`apply_script_writes`]).

use bevy_ecs::prelude::{DetectChangesMut, Entity, Mut, Query, Res, ResMut, World};
use glam::{DVec3, Vec3};

use super::{
    degrees_from_rotation, rotation_from_degrees, CameraState, EntityKind, EntityState, FocusState,
    LightTerms, MaterialParams, MaterialState, ScriptState, SettingsState, SharedState,
};
use crate::geom;
use crate::sample::adaptive::AdaptiveSettings;
use crate::scene::format::LightDesc;
use crate::script::texture::{apply_texture_writes, texture_states};
use crate::store::MaterialId;
use crate::trace::{self};
use crate::world::components::{Light, MaterialRef, Name, Shape, Transform, Visible};
use crate::world::resources::{CameraRig, Focus, Materials, SceneSettings, Textures};

/// The light's position as scripts see it: a point light's position, an area light's centre
/// (`None` for directional lights).
pub(super) fn light_position(light: &Light) -> Option<DVec3> {
    let anchor = light.position()?;
    match light.source {
        trace::Light::Rect { edge_u, edge_v, .. } => Some(anchor + 0.5 * (edge_u + edge_v).as_dvec3()),
        _ => Some(anchor),
    }
}

/// The light's radiance (colour × intensity).
fn light_radiance(light: &trace::Light) -> Vec3 {
    match *light {
        trace::Light::Point { radiance, .. }
        | trace::Light::Spot { radiance, .. }
        | trace::Light::Directional { radiance, .. }
        | trace::Light::Rect { radiance, .. }
        | trace::Light::Disk { radiance, .. } => radiance,
    }
}

/// The light with its radiance set to `to`.
fn relit(light: &trace::Light, to: Vec3) -> trace::Light {
    let mut relit = *light;
    match &mut relit {
        trace::Light::Point { radiance, .. }
        | trace::Light::Spot { radiance, .. }
        | trace::Light::Directional { radiance, .. }
        | trace::Light::Rect { radiance, .. }
        | trace::Light::Disk { radiance, .. } => *radiance = to,
    }
    relit
}

/// The light moved so that its position (as [`light_position`] defines it) is `to`.
pub(super) fn moved_light(light: &Light, to: DVec3) -> Light {
    match light.source {
        trace::Light::Directional { .. } => *light,
        trace::Light::Rect { edge_u, edge_v, .. } => {
            Light::at(to - 0.5 * (edge_u + edge_v).as_dvec3(), light.source)
        }
        _ => Light::at(to, light.source),
    }
}

impl ScriptState {
    /// The mirror of a World holding a spawned scene.
    pub fn from_world(world: &mut World) -> Self {
        let rig = *world.resource::<CameraRig>();
        let scene = *world.resource::<SceneSettings>();
        let s = scene.render;
        let materials = world.resource::<Materials>().table.clone();
        let mut state = ScriptState {
            camera: CameraState {
                position: rig.position,
                look_at: rig.look_at,
                up: rig.up.as_dvec3(),
                fov_deg: (rig.fov_y as f64).to_degrees(),
                aperture: rig.aperture as f64,
                focus: match rig.focus {
                    Focus::LookAt => FocusState::LookAt,
                    Focus::Distance(d) => FocusState::Distance(d as f64),
                    Focus::Point(p) => FocusState::Point(p),
                },
            },
            settings: SettingsState {
                width: s.width,
                height: s.height,
                samples: s.aa.samples,
                lens_samples: s.lens.samples,
                time_samples: s.time.samples,
                glossy_samples: s.glossy.samples,
                adaptive: s.adaptive.map(|a| (a.threshold as f64, a.max_depth)),
                max_depth: s.max_depth,
                background: scene.background,
                ambient: scene.ambient,
                max_secondary_rays: s.max_secondary_rays,
                seed: s.seed,
            },
            textures: world.get_resource::<Textures>().map(texture_states).unwrap_or_default(),
            ..Default::default()
        };

        let mut named: Vec<(Entity, String)> =
            world.query::<(Entity, &Name)>().iter(world).map(|(e, n)| (e, n.as_str().to_owned())).collect();
        named.sort_unstable_by_key(|(e, _)| *e);
        for (entity, name) in named {
            let e = world.entity(entity);
            let visible = e.get::<Visible>().is_none_or(|v| v.0);
            let mut entry = EntityState {
                entity,
                name: name.clone(),
                kind: EntityKind::Light { positioned: false },
                position: DVec3::ZERO,
                rotation_deg: DVec3::ZERO,
                scale: DVec3::ONE,
                visible,
                material: None,
                faces_own_materials: false,
                light: None,
                transform_dirty: false,
                rotation_written: false,
                visible_dirty: false,
                material_dirty: false,
                light_dirty: false,
            };
            if let (Some(shape), Some(t)) = (e.get::<Shape>(), e.get::<Transform>()) {
                let bounds = shape.0.bounds();
                let pivot = match &shape.0 {
                    geom::Shape::Plane { point, .. } => *point,
                    _ => bounds.map_or(DVec3::ZERO, |(min, max)| 0.5 * (min + max)),
                };
                let uniform_scale = matches!(shape.0, geom::Shape::Sphere { .. });
                entry.kind = EntityKind::Object { pivot, uniform_scale, bounds };
                entry.position = t.translation;
                entry.rotation_deg = degrees_from_rotation(t.rotation);
                entry.scale = t.scale.as_dvec3();
                entry.faces_own_materials = match &shape.0 {
                    geom::Shape::Mesh { mesh, .. } => world
                        .get_resource::<crate::world::resources::MeshTable>()
                        .and_then(|t| t.0.get(mesh.0 as usize))
                        .is_some_and(|a| !a.data.face_material.is_empty()),
                    _ => false,
                };
                entry.material = e
                    .get::<MaterialRef>()
                    .filter(|_| !entry.faces_own_materials)
                    .and_then(|m| materials.get(m.0 .0 as usize))
                    .map(|m| MaterialState { params: MaterialParams::from(m), private: None });
            } else if let Some(light) = e.get::<Light>() {
                let position = light_position(light);
                entry.kind = EntityKind::Light { positioned: position.is_some() };
                entry.position = position.unwrap_or(DVec3::ZERO);
                // The World keeps only the product; `adopt_light_terms` restores the file's split.
                entry.light =
                    Some(LightTerms { colour: light_radiance(&light.source).as_dvec3(), intensity: 1.0 });
            } else {
                continue;
            }
            state.by_name.insert(name, state.entities.len());
            state.entities.push(entry);
        }
        state
    }

    /// Takes each light's colour and intensity from the scene it was spawned from (`lights[i]`
    /// is the entity `light_i`), where the World's radiance still equals their product; without
    /// this a light reads as its radiance with intensity 1.
    pub fn adopt_light_terms(&mut self, lights: &[LightDesc]) {
        for (i, desc) in lights.iter().enumerate() {
            let Some(index) = self.index_of(&format!("light_{i}")) else { continue };
            let entry = &mut self.entities[index];
            let (colour, intensity) = match *desc {
                LightDesc::Point { colour, intensity, .. }
                | LightDesc::Spot { colour, intensity, .. }
                | LightDesc::Directional { colour, intensity, .. }
                | LightDesc::Rect { colour, intensity, .. }
                | LightDesc::Disk { colour, intensity, .. } => (colour, intensity),
            };
            if let Some(terms) = entry.light.as_mut().filter(|t| t.colour.as_vec3() == colour * intensity) {
                *terms = LightTerms { colour: colour.as_dvec3(), intensity: intensity as f64 };
            }
        }
    }
}

/// The World's input system: moves the script's writes into components and resources with
/// `set_if_neq`, then clears the record of writes.
#[allow(clippy::type_complexity)]
pub fn apply_script_writes(
    shared: Res<SharedState>,
    mut objects: Query<(
        Option<&mut Transform>,
        Option<&mut Visible>,
        Option<&mut MaterialRef>,
        Option<&mut Light>,
    )>,
    mut materials: ResMut<Materials>,
    textures: Option<ResMut<Textures>>,
    mut rig: ResMut<CameraRig>,
    mut settings: ResMut<SceneSettings>,
) {
    let mut state = shared.lock();
    apply_texture_writes(&mut state.textures, textures.map(Into::into));
    if state.camera_dirty || state.focus_follows_entity() {
        rig.set_if_neq(state.rig());
    }
    if state.settings_dirty {
        let s = state.settings;
        let mut next = settings.render;
        next.width = s.width;
        next.height = s.height;
        next.aa.samples = s.samples;
        next.lens.samples = s.lens_samples;
        next.time.samples = s.time_samples;
        next.glossy.samples = s.glossy_samples;
        next.adaptive = s
            .adaptive
            .map(|(threshold, max_depth)| AdaptiveSettings { threshold: threshold as f32, max_depth });
        next.max_depth = s.max_depth;
        next.max_secondary_rays = s.max_secondary_rays;
        next.seed = s.seed;
        if settings.render != next {
            settings.render = next;
        }
    }
    let frame = state.clock.frame;
    if settings.render.frame != frame {
        settings.render.frame = frame;
    }
    state.camera_dirty = false;
    state.settings_dirty = false;

    for entry in state.entities.iter_mut() {
        if !(entry.transform_dirty || entry.visible_dirty || entry.material_dirty || entry.light_dirty) {
            continue;
        }
        let Ok((transform, visible, material_ref, light)) = objects.get_mut(entry.entity) else {
            continue;
        };
        if let (true, Some(mut transform)) = (entry.transform_dirty, transform) {
            let rotation = match entry.rotation_written {
                true => rotation_from_degrees(entry.rotation_deg),
                false => transform.rotation,
            };
            transform.set_if_neq(Transform {
                translation: entry.position,
                rotation,
                scale: entry.scale.as_vec3(),
            });
        }
        if let (true, Some(mut light)) = (entry.transform_dirty || entry.light_dirty, light) {
            let mut next = *light;
            if entry.transform_dirty {
                next = moved_light(&next, entry.position);
            }
            if let (true, Some(terms)) = (entry.light_dirty, entry.light) {
                next.source = relit(&next.source, (terms.colour * terms.intensity).as_vec3());
            }
            light.set_if_neq(next);
        }
        if entry.visible_dirty {
            if let Some(mut visible) = visible {
                visible.set_if_neq(Visible(entry.visible));
            }
        }
        if let (true, Some(material_ref), Some(m)) =
            (entry.material_dirty, material_ref, entry.material.as_mut())
        {
            apply_material(&entry.name, m, material_ref, &mut materials);
        }
        entry.transform_dirty = false;
        entry.visible_dirty = false;
        entry.material_dirty = false;
        entry.light_dirty = false;
    }
}

/// Writes an entity's material parameters: into its private copy, made on the first write
/// that differs from the shared scene material.
fn apply_material(
    name: &str,
    m: &mut MaterialState,
    mut material_ref: Mut<MaterialRef>,
    materials: &mut Materials,
) {
    let wanted = m.params.to_material();
    let id = match m.private {
        Some(id) => id,
        // Unchanged from the shared material: keep sharing it.
        None if materials.table.get(material_ref.0 .0 as usize) == Some(&wanted) => return,
        None => {
            let id = MaterialId(materials.table.len() as u32);
            materials.table.push(wanted);
            materials.names.push(format!("{name}#script"));
            m.private = Some(id);
            id
        }
    };
    material_ref.set_if_neq(MaterialRef(id));
    if materials.table[id.0 as usize] != wanted {
        materials.table[id.0 as usize] = wanted;
    }
}
