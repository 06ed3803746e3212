#pragma once
// Eigen cuts its dense matrix products into blocks sized from the CPU's caches
// (CPUID), and the depth of a block decides how each product's sums are
// grouped: a CPU with a 48 KiB L1 data cache (Intel since Ice Lake) rounds
// them differently from one with 32 KiB. Fixed sizes make every x86-64 CPU
// group them alike (README.md, "Reproducibility").

namespace gp {

// Eigen's cache sizes for the whole process, fixed at L1 32 KiB, L2 1 MiB and
// L3 32 MiB. Call it before any thread multiplies; every stage does (gp::Tool)
// and so does every test executable.
void fix_dense_blocking();

}  // namespace gp
