#pragma once
// transitional: removed after the merge of s7-sub. MultiEmulatedBench is EmulatedBench (n
// actuators, emulated_bench.h); MultiBenchConfig is EmulatedBenchSpec (bench_spec.h).
#include "hybridtest/transfer/bench_spec.h"
#include "hybridtest/transfer/emulated_bench.h"
