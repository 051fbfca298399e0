//! Parameter ids by name, without a second copy of the names.
//!
//! A whole mesh declares millions of parameters; a `HashMap<String, ParamId>` beside the
//! parameter list held every name twice (and 32 bytes of table per name). This table holds only
//! the ids, hashed by their parameter's name, and looks names up in the parameter list.

use crate::system::{ParamId, Parameter};
use std::hash::BuildHasher;

/// Ids of `params` hashed by `params[id].name` (foldhash: names are short and many).
#[derive(Clone, Default)]
pub(crate) struct NameIndex {
    table: hashbrown::HashTable<ParamId>,
    state: foldhash::fast::RandomState,
}

impl NameIndex {
    /// The id of the parameter named `name`, if any.
    pub(crate) fn get(&self, params: &[Parameter], name: &str) -> Option<ParamId> {
        self.table
            .find(self.state.hash_one(name), |id| {
                *params[id.index()].name == *name
            })
            .copied()
    }

    /// Records `id`, whose parameter `params[id]` is already in the list and whose name is not
    /// yet in the index.
    pub(crate) fn insert(&mut self, params: &[Parameter], id: ParamId) {
        let state = &self.state;
        self.table
            .insert_unique(state.hash_one(&params[id.index()].name), id, |other| {
                state.hash_one(&params[other.index()].name)
            });
    }

    /// Forgets `id` (its parameter must still be in `params`).
    pub(crate) fn remove(&mut self, params: &[Parameter], id: ParamId) {
        let hash = self.state.hash_one(&params[id.index()].name);
        if let Ok(entry) = self.table.find_entry(hash, |other| *other == id) {
            entry.remove();
        }
    }

    /// Makes room for `additional` more names.
    pub(crate) fn reserve(&mut self, params: &[Parameter], additional: usize) {
        let state = &self.state;
        self.table
            .reserve(additional, |id| state.hash_one(&params[id.index()].name));
    }
}

impl std::fmt::Debug for NameIndex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "NameIndex({} names)", self.table.len())
    }
}
