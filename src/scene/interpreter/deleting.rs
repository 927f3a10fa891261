//! `delobj n...` (004 appendix B, the plytrace manual page: "delete
//! objects"). The objects that `delobj` statements in a row delete are
//! marked, and leave the scene together before any other statement runs
//! (and when the interpreter stops or hands out its scene): deleting
//! them one statement at a time shifted every object after each, so a
//! scene deleting its 20,000 objects one by one took 3.3 s, growing as
//! n^2. The first reference of a run is found by a scan, as a lone
//! deletion between other statements costs no more than before; from the
//! second on, the numbers and names are looked up once for the run.

use std::collections::HashMap;

use crate::model::Object;
use crate::scene::arguments::ObjectRef;

/// The objects marked by `delobj` statements in a row, by index in the
/// scene's objects (which do not change while they are marked).
#[derive(Debug, Clone)]
pub(in crate::scene) struct Doomed {
    gone: Vec<bool>,
    /// References marked so far.
    references: usize,
    /// The objects of each number not yet named; made at the first
    /// reference by number.
    numbers: Option<HashMap<u32, Vec<usize>>>,
    /// The objects of each name not yet named; made at the first
    /// reference by name.
    names: Option<HashMap<String, Vec<usize>>>,
}

impl Doomed {
    /// Nothing marked among `count` objects.
    pub(in crate::scene) fn new(count: usize) -> Doomed {
        Doomed {
            gone: vec![false; count],
            references: 0,
            numbers: None,
            names: None,
        }
    }

    /// Marks the objects of `objects` that `r` names; whether one of them
    /// was not marked already (else nothing by that name is left).
    pub(in crate::scene) fn mark(&mut self, objects: &[Object], r: &ObjectRef) -> bool {
        self.references += 1;
        if self.references == 1 {
            let named = objects.iter().enumerate().filter(|(_, o)| r.names(o));
            return self.mark_all(named.map(|(k, _)| k));
        }
        let named = match r {
            ObjectRef::Number(n) => self
                .numbers
                .get_or_insert_with(|| index(objects, |o| o.number))
                .remove(n),
            ObjectRef::Name(name) => self
                .names
                .get_or_insert_with(|| index(objects, |o| o.name.clone()))
                .remove(name),
        };
        // Each list is walked once: a second reference to it finds it gone.
        self.mark_all(named.into_iter().flatten())
    }

    /// Marks objects `ks`; whether one was not marked already.
    fn mark_all(&mut self, ks: impl Iterator<Item = usize>) -> bool {
        let mut found = false;
        for k in ks {
            found |= !std::mem::replace(&mut self.gone[k], true);
        }
        found
    }

    /// Whether object `k` is marked.
    pub(in crate::scene) fn is_gone(&self, k: usize) -> bool {
        self.gone[k]
    }
}

/// The indices of `objects` by `key`.
fn index<K: std::hash::Hash + Eq>(
    objects: &[Object],
    key: impl Fn(&Object) -> K,
) -> HashMap<K, Vec<usize>> {
    let mut map: HashMap<K, Vec<usize>> = HashMap::new();
    for (k, o) in objects.iter().enumerate() {
        map.entry(key(o)).or_default().push(k);
    }
    map
}
