//! Hard cases of instancing: closed meshes placed far from the origin, mirrored, scaled from
//! 1e-6 to 1e6, shot through their vertices and edges: never a leak, and the hit agrees with
//! an `f64` oracle (the flattened triangle in `f64`) within the transform's rounding.
