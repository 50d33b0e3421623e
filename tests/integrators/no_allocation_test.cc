// ExplicitRungeKutta::Step does no heap allocation (a real-time requirement: the step runs
// between actuator commands). This file counts calls to malloc/calloc/realloc by replacing them
// in this test program with forwarders to glibc's own implementation (glibc supports replacing
// malloc). Eigen allocates with std::malloc, operator new calls malloc, so both are seen.
// Under AddressSanitizer, which owns malloc itself, the test is skipped.
#include <atomic>
#include <cstddef>

#include <gtest/gtest.h>

#include "hybridtest/integrators/catalogue.h"
#include "hybridtest/integrators/explicit_runge_kutta.h"

#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
#define HYBRIDTEST_COUNT_MALLOC 1
#endif

namespace {
std::atomic<bool> g_counting{false};
std::atomic<long> g_allocations{0};
}  // namespace

#ifdef HYBRIDTEST_COUNT_MALLOC
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* pointer, std::size_t size);

void* malloc(std::size_t size) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  return __libc_calloc(count, size);
}
void* realloc(void* pointer, std::size_t size) noexcept {
  if (g_counting.load(std::memory_order_relaxed)) g_allocations.fetch_add(1);
  return __libc_realloc(pointer, size);
}
}  // extern "C"
#endif

namespace hybridtest::integrators {
namespace {

// Counts heap allocations made while `body` runs.
template <class Body>
long CountAllocations(Body&& body) {
  g_allocations = 0;
  g_counting = true;
  body();
  g_counting = false;
  return g_allocations.load();
}

class NoAllocationTest : public ::testing::Test {
 protected:
  void SetUp() override {
#ifndef HYBRIDTEST_COUNT_MALLOC
    GTEST_SKIP() << "malloc cannot be counted in this build (sanitizer or non-glibc)";
#endif
  }
};

TEST_F(NoAllocationTest, CounterSeesEigenAndOperatorNew) {
  // Positive control: without it, the test below could pass by counting nothing.
  EXPECT_GE(CountAllocations([] {
              Eigen::VectorXd v(64);
              v.setZero();
              EXPECT_EQ(v.sum(), 0.0);
            }),
            1);
  EXPECT_GE(CountAllocations([] {
              // volatile: the compiler may otherwise elide a new/delete pair.
              static double* volatile sink = nullptr;
              sink = new double(1.0);
              delete sink;
            }),
            1);
}

TEST_F(NoAllocationTest, StepDoesNotAllocate) {
  constexpr int kN = 8;
  for (const ButcherTableau& tableau : Catalogue()) {
    ExplicitRungeKutta stepper(tableau, kN);
    const Eigen::MatrixXd J = -Eigen::MatrixXd::Identity(kN, kN);
    Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(kN, 0.0, 1.0);
    Eigen::VectorXd x_next(kN);
    auto stage = [&](int, double t_i, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
      for (int r = 0; r < kN; ++r) k(r) = J.row(r).dot(x_i) + t_i;
    };
    const long allocations = CountAllocations([&] {
      for (int n = 0; n < 10; ++n) {
        stepper.Step(n * 0.01, 0.01, x, stage, x_next);
        stepper.Step(n * 0.01, 0.01, x_next, stage, x_next);  // in place
      }
    });
    EXPECT_EQ(allocations, 0) << tableau.name;
    EXPECT_TRUE(x_next.allFinite());
  }
}

TEST_F(NoAllocationTest, StepAllocatesOnlyToResizeAWronglySizedOutput) {
  // Positive control through Step itself: the documented one allocation is seen.
  ExplicitRungeKutta stepper(FindTableau("rk4"), 4);
  const Eigen::VectorXd x = Eigen::VectorXd::Ones(4);
  Eigen::VectorXd x_next;
  auto stage = [](int, double, const Eigen::VectorXd& x_i, Eigen::Ref<Eigen::VectorXd> k) {
    for (Eigen::Index r = 0; r < x_i.size(); ++r) k(r) = -x_i(r);
  };
  EXPECT_EQ(CountAllocations([&] { stepper.Step(0.0, 0.1, x, stage, x_next); }), 1);
  EXPECT_EQ(CountAllocations([&] { stepper.Step(0.0, 0.1, x, stage, x_next); }), 0);
}

}  // namespace
}  // namespace hybridtest::integrators
