// The Pareto front of `beamtrace trade`: the settings no other setting beats in both speed and error.
#include <gtest/gtest.h>

#include "beamtrace/error.hpp"
#include "experiments/trade_plot.hpp"

using beamtrace::workload::pareto_front;

TEST(ParetoFront, KeepsOnlyUnbeatenPointsSortedByError) {
    //                          0     1     2     3     4     5
    const std::vector<double> error = {0.0, 0.0, 0.01, 0.02, 0.05, 0.03};
    const std::vector<double> speed = {1.0, 2.0, 1.5, 4.0, 3.0, 4.0};
    // 0 is beaten by 1 (same error, faster); 2 by 1 (less error, faster); 4 and 5 by 3.
    EXPECT_EQ(pareto_front(error, speed), (std::vector<std::size_t>{1, 3}));
}

TEST(ParetoFront, EqualPointsKeepTheFirst) {
    EXPECT_EQ(pareto_front({0.1, 0.1, 0.1}, {2.0, 2.0, 1.0}), (std::vector<std::size_t>{0}));
}

TEST(ParetoFront, EveryPointOfAStaircaseIsOnIt) {
    EXPECT_EQ(pareto_front({0.3, 0.0, 0.1, 0.2}, {4.0, 1.0, 2.0, 3.0}), (std::vector<std::size_t>{1, 2, 3, 0}));
}

TEST(ParetoFront, EmptyAndMismatchedInputs) {
    EXPECT_TRUE(pareto_front({}, {}).empty());
    EXPECT_THROW(pareto_front({0.0}, {}), beamtrace::Error);
}
