// parallelBlocks: every item once, for any number of threads, and progress on the calling thread.
#include <gtest/gtest.h>

#include <stdexcept>
#include <thread>

#include "geobrush/parallel.hpp"

using geobrush::parallelBlocks;

TEST(ParallelBlocks, VisitsEveryItemOnceForAnyThreadCount) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<int> visits(1000, 0);
    parallelBlocks(visits.size(), 7, threads, [&](std::size_t first, std::size_t last) {
      for (std::size_t i = first; i < last; ++i)
        ++visits[i];
    });
    EXPECT_EQ(std::count(visits.begin(), visits.end(), 1), 1000) << threads << " threads";
  }
}

TEST(ParallelBlocks, ReportsRisingProgressOnTheCallingThreadEndingAtOne) {
  for (int threads : {1, 4}) {
    std::vector<double> reports;
    const auto caller = std::this_thread::get_id();
    bool otherThread = false;
    parallelBlocks(
        100, 10, threads, [](std::size_t, std::size_t) {},
        [&](double fraction) {
          otherThread |= std::this_thread::get_id() != caller;
          reports.push_back(fraction);
        });
    EXPECT_FALSE(otherThread);
    ASSERT_FALSE(reports.empty());
    EXPECT_TRUE(std::is_sorted(reports.begin(), reports.end()));
    EXPECT_GT(reports.front(), 0.0);
    EXPECT_EQ(reports.back(), 1.0);
    EXPECT_EQ(std::count(reports.begin(), reports.end(), 1.0), 1);
  }
}

TEST(ParallelBlocks, WhatProgressThrowsStopsTheLoopAndIsRethrown) {
  std::size_t blocksRun = 0;
  EXPECT_THROW(parallelBlocks(
                   100, 1, 1, [&](std::size_t, std::size_t) { ++blocksRun; },
                   [](double fraction) {
                     if (fraction >= 0.05) throw std::runtime_error("cancelled");
                   }),
               std::runtime_error);
  EXPECT_EQ(blocksRun, 5u);
}
