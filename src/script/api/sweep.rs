//! Sweep helpers: `product(#{ a: [..], b: [..] })`, every combination of the listed values.

use rhai::{Array, Dynamic, Engine, Map};

use super::convert::{error, ScriptResult};

/// Registers `product`.
pub fn register(engine: &mut Engine) {
    engine.register_fn("product", product);
}

/// Every combination of the values listed under each key, as object maps. Keys vary in
/// alphabetical order (Rhai's map order), the last key fastest.
pub fn product(axes: Map) -> ScriptResult<Array> {
    let mut sets: Vec<Map> = vec![Map::new()];
    for (key, values) in axes {
        let Some(values) = values.clone().try_cast::<Array>() else {
            return error(format!("product: `{key}` must be an array of values, got {}", values.type_name()));
        };
        if values.is_empty() {
            return error(format!("product: `{key}` lists no values"));
        }
        sets = sets
            .into_iter()
            .flat_map(|set| {
                let key = key.clone();
                values.iter().map(move |v| {
                    let mut next = set.clone();
                    next.insert(key.clone(), v.clone());
                    next
                })
            })
            .collect();
    }
    Ok(sets.into_iter().map(Dynamic::from_map).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn product_enumerates_every_combination_last_key_fastest() {
        let mut engine = Engine::new();
        register(&mut engine);
        let sets: Array = engine.eval("product(#{ aperture: [0.0, 0.1], samples: [1, 4, 16] })").unwrap();
        let pairs: Vec<(f64, i64)> = sets
            .into_iter()
            .map(|s| {
                let m = s.cast::<Map>();
                (m["aperture"].as_float().unwrap(), m["samples"].as_int().unwrap())
            })
            .collect();
        assert_eq!(pairs, [(0.0, 1), (0.0, 4), (0.0, 16), (0.1, 1), (0.1, 4), (0.1, 16)]);
        assert!(engine.eval::<Array>("product(#{ a: 3 })").is_err());
        assert!(engine.eval::<Array>("product(#{ a: [] })").is_err());
    }
}
