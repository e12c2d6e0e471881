"""Shared pieces of the lumis cross-check tools: an independent scene loader, an Embree + float64
oracle, seeded ray sets, id mapping by position, and a runner for `lumis hits`."""
