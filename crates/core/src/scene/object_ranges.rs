//! Which object owns a primitive: objects own consecutive ranges of primitives, in object order.

/// The primitive ranges of a scene's objects.
#[derive(Clone, Debug, Default)]
pub(crate) struct ObjectRanges {
    /// The first primitive of each object (an empty object shares its start with the next one
    /// and owns nothing).
    starts: Vec<u32>,
    /// The object of each primitive, for scenes of many small objects (every `.scn` shape is
    /// one): there a search over the starts cost ~190 instructions per hit record (callgrind,
    /// tumbledStones), and the table costs at most `4 * DENSE` bytes per object. Empty for
    /// scenes of few or large objects, where the search is short and a table would cost 4
    /// bytes per primitive and a cache miss per hit record on a large mesh.
    table: Vec<u32>,
}

/// At most this many primitives per object on average, and at least [`MIN_OBJECTS`] objects,
/// for the per-primitive table.
const DENSE: usize = 8;
/// One object needs neither.
const MIN_OBJECTS: usize = 2;

impl ObjectRanges {
    /// The ranges starting at `starts`, over `prims` primitives in all.
    pub(crate) fn new(starts: Vec<u32>, prims: usize) -> Self {
        let table = if starts.len() >= MIN_OBJECTS && prims <= DENSE * starts.len() {
            let mut table = Vec::with_capacity(prims);
            for object in 0..starts.len() {
                let end = starts.get(object + 1).map_or(prims, |&s| s as usize);
                table.resize(end.max(table.len()), object as u32);
            }
            table
        } else {
            Vec::new()
        };
        Self { starts, table }
    }

    /// The object owning primitive `prim`.
    #[inline]
    pub(crate) fn object_of(&self, prim: u32) -> u32 {
        if let Some(&object) = self.table.get(prim as usize) {
            return object;
        }
        match self.starts.as_slice() {
            [] | [_] => 0,
            // The last object starting at or before `prim`.
            starts => (starts.partition_point(|&s| s <= prim) - 1) as u32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table and the search agree on every primitive, with empty objects between.
    #[test]
    fn table_matches_search() {
        let mut starts = Vec::new();
        let mut prim = 0u32;
        for object in 0..40u32 {
            starts.push(prim);
            prim += object % 3; // sizes 0, 1, 2: empty objects among them
        }
        let dense = ObjectRanges::new(starts.clone(), prim as usize);
        assert_eq!(dense.table.len(), prim as usize);
        let sparse = ObjectRanges {
            starts: starts.clone(),
            table: Vec::new(),
        };
        for p in 0..prim {
            let expected = starts.iter().rposition(|&s| s <= p).unwrap() as u32;
            assert_eq!(dense.object_of(p), expected, "primitive {p}");
            assert_eq!(sparse.object_of(p), expected, "primitive {p}");
        }
    }

    /// Few or large objects get no table.
    #[test]
    fn no_table_for_large_objects() {
        let ranges = ObjectRanges::new(vec![0, 1000, 2000], 3000);
        assert!(ranges.table.is_empty());
        assert_eq!(ranges.object_of(1500), 1);
        let big: Vec<u32> = (0..20).map(|i| i * 100).collect();
        assert!(ObjectRanges::new(big, 2000).table.is_empty());
    }
}
