// The lesson's early-out analysis as functions; CheckChain (header) applies them online.

#include <collide/early_out/check_chain.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace collide {

double cost_per_rejection(const CheckStats& check) noexcept {
  if (check.cost <= 0.0) return 0.0;
  const double reject = 1.0 - check.pass_rate;
  return reject > 0.0 ? check.cost / reject : std::numeric_limits<double>::infinity();
}

double expected_cost(std::span<const CheckStats> checks, std::span<const int> order) noexcept {
  double total = 0.0;
  double reach = 1.0;  // probability that every earlier check passed
  for (const int i : order) {
    total += reach * checks[static_cast<size_t>(i)].cost;
    reach *= checks[static_cast<size_t>(i)].pass_rate;
  }
  return total;
}

void optimal_order(std::span<const CheckStats> checks, std::span<int> order) {
  if (order.size() != checks.size()) {
    throw InvalidInput("optimal_order: order has " + std::to_string(order.size()) +
                       " slots for " + std::to_string(checks.size()) + " checks");
  }
  for (size_t i = 0; i < checks.size(); ++i) {
    if (!std::isfinite(checks[i].cost) || checks[i].cost < 0.0) {
      throw InvalidInput("optimal_order: check " + std::to_string(i) + " cost must be finite and >= 0");
    }
    if (!(checks[i].pass_rate >= 0.0 && checks[i].pass_rate <= 1.0)) {
      throw InvalidInput("optimal_order: check " + std::to_string(i) + " pass rate must be in [0, 1]");
    }
    order[i] = static_cast<int>(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return cost_per_rejection(checks[static_cast<size_t>(a)]) <
           cost_per_rejection(checks[static_cast<size_t>(b)]);
  });
}

double cost_with_pretest(const CheckStats& pretest, double exact_cost) noexcept {
  return pretest.cost + pretest.pass_rate * exact_cost;
}

bool pretest_pays(const CheckStats& pretest, double exact_cost) noexcept {
  return pretest.cost < (1.0 - pretest.pass_rate) * exact_cost;
}

}  // namespace collide
