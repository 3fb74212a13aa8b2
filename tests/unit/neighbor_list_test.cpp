// The Verlet list against brute force, and contact history across rebuilds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <map>
#include <numeric>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "bushel/contact/neighbor_list.hpp"
#include "bushel/core/input_error.hpp"
#include "bushel/io/binary_archive.hpp"

namespace bushel {
namespace {

struct Cloud {
  std::vector<Vec3> position;
  std::vector<double> radius;
  std::vector<std::uint32_t> owner, id;
};

Cloud random_cloud(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 0.02), r(0.5e-3, 1.5e-3);
  Cloud c;
  for (std::size_t i = 0; i < n; ++i) {
    c.position.push_back({u(rng), u(rng), u(rng)});
    c.radius.push_back(r(rng));
    c.owner.push_back(static_cast<std::uint32_t>(i / 3));  // clumps of three elements
    c.id.push_back(static_cast<std::uint32_t>(1000 + i));
  }
  return c;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> brute_force(const Cloud& c, double skin) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> s;
  for (std::uint32_t i = 0; i < c.position.size(); ++i) {
    for (std::uint32_t j = i + 1; j < c.position.size(); ++j) {
      const double reach = c.radius[i] + c.radius[j] + skin;
      if (c.owner[i] != c.owner[j] && norm2(c.position[i] - c.position[j]) < reach * reach) s.insert({i, j});
    }
  }
  return s;
}

// Pairs within r_i + r_j + m_i + m_j, margins m per element.
std::set<std::pair<std::uint32_t, std::uint32_t>> brute_force(const Cloud& c, const std::vector<double>& margin) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> s;
  for (std::uint32_t i = 0; i < c.position.size(); ++i) {
    for (std::uint32_t j = i + 1; j < c.position.size(); ++j) {
      const double reach = c.radius[i] + c.radius[j] + (margin[i] + margin[j]);
      if (c.owner[i] != c.owner[j] && norm2(c.position[i] - c.position[j]) < reach * reach) s.insert({i, j});
    }
  }
  return s;
}

std::set<std::pair<std::uint32_t, std::uint32_t>> listed(const NeighborList& list) {
  std::set<std::pair<std::uint32_t, std::uint32_t>> found;
  for (std::size_t p = 0; p < list.pairs(); ++p) found.insert({list.first(p), list.second(p)});
  return found;
}

// As the simulation asks: whether any element has moved past its margin since the build.
bool rebuild_due(const NeighborList& list, const Cloud& c) {
  double worst = -1.0;
  for (std::size_t k = 0; k < c.position.size(); ++k) {
    worst = std::max(worst, list.excess2(k, list.displacement2(k, c.position[k])));
  }
  return list.needs_rebuild(worst);
}

TEST(NeighborList, MatchesBruteForce) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const Cloud c = random_cloud(900, seed);
    NeighborList list(0.4e-3, 3);
    list.build(c.position, c.radius, c.owner, c.id);
    std::set<std::pair<std::uint32_t, std::uint32_t>> found;
    for (std::size_t p = 0; p < list.pairs(); ++p) {
      EXPECT_LT(list.first(p), list.second(p));
      found.insert({list.first(p), list.second(p)});
    }
    EXPECT_EQ(found.size(), list.pairs()) << "duplicate pairs";
    EXPECT_EQ(found, brute_force(c, 0.4e-3));
  }
}

// Pairs a hair inside and outside the reach, on cell boundaries: the scan skips cells and rows
// of cells out of an element's reach, which must never cost a pair to rounding.
TEST(NeighborList, MatchesBruteForceAtTheEdgeOfReach) {
  const double r = 1e-3, skin = 0.4e-3, reach = 2 * r + skin;
  for (const double spacing : {reach * (1 - 1e-12), reach * (1 + 1e-12), reach / std::sqrt(2.0) * (1 - 1e-12),
                               reach / std::sqrt(3.0) * (1 - 1e-12), 0.25 * reach}) {
    Cloud c;
    for (int x = 0; x < 7; ++x) {
      for (int y = 0; y < 7; ++y) {
        for (int z = 0; z < 7; ++z) {
          c.position.push_back({x * spacing, y * spacing, z * spacing});
          c.radius.push_back(r);
          c.owner.push_back(static_cast<std::uint32_t>(c.owner.size()));
          c.id.push_back(static_cast<std::uint32_t>(c.id.size()));
        }
      }
    }
    NeighborList list(skin, 3);
    list.build(c.position, c.radius, c.owner, c.id);
    EXPECT_EQ(listed(list), brute_force(c, skin)) << "spacing " << spacing;
  }
}

// A partner a hair inside the reach and just past a cell boundary (the grid starts at the
// lowest element, and its cells are a reach wide).
TEST(NeighborList, FindsAPartnerJustPastACellBoundary) {
  const double r = 1e-3, skin = 0.4e-3, reach = 2 * r + skin, delta = 1e-10 * reach;
  for (int axis = 0; axis < 3; ++axis) {
    const auto at = [&](double d) { return Vec3{axis == 0 ? d : 0.0, axis == 1 ? d : 0.0, axis == 2 ? d : 0.0}; };
    Cloud c;
    c.position = {at(0.0), at(delta), at(delta + reach * (1 - 1e-12))};
    c.radius = {r, r, r};
    c.owner = {0, 1, 2};
    c.id = {0, 1, 2};
    ASSERT_EQ(brute_force(c, skin).count({1, 2}), 1u);
    NeighborList list(skin, 3);
    list.build(c.position, c.radius, c.owner, c.id);
    EXPECT_EQ(listed(list), brute_force(c, skin)) << "axis " << axis;
  }
}

// A few elements with wide margins (up to four times half the skin) among narrow ones: the
// same pairs as brute force, each once, grouped by first element and sorted.
TEST(NeighborList, MarginsPerElementMatchBruteForce) {
  const double skin = 0.4e-3;
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const Cloud c = random_cloud(900, seed);
    std::mt19937_64 rng(seed + 10);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<double> margin(c.position.size(), 0.5 * skin);
    for (double& m : margin) {
      if (u(rng) < 0.05) m *= 1.0 + 3.0 * u(rng);
    }
    NeighborList list(skin, 3);
    list.build(c.position, c.radius, c.owner, c.id, margin);
    for (std::size_t p = 1; p < list.pairs(); ++p) {
      EXPECT_TRUE(list.first(p - 1) < list.first(p) ||
                  (list.first(p - 1) == list.first(p) && list.second(p - 1) < list.second(p)));
    }
    for (std::size_t i = 0; i < c.position.size(); ++i) {
      for (std::size_t p = list.begin_of(i); p < list.begin_of(i + 1); ++p) EXPECT_EQ(list.first(p), i);
    }
    const auto found = listed(list);
    EXPECT_EQ(found.size(), list.pairs()) << "duplicate pairs";
    EXPECT_EQ(found, brute_force(c, margin));
    EXPECT_GT(found.size(), brute_force(c, skin).size());
  }
}

// Each element may move as far as its own margin before a rebuild is due.
TEST(NeighborList, RebuildOnlyAfterAnElementPassesItsMargin) {
  Cloud c = random_cloud(50, 5);
  NeighborList list(1e-3, 0);
  std::vector<double> margin(c.position.size(), 0.5e-3);
  margin[17] = 2e-3;
  list.build(c.position, c.radius, c.owner, c.id, margin);
  EXPECT_DOUBLE_EQ(list.margin(17), 2e-3);
  c.position[17].x += 1.99e-3;
  EXPECT_FALSE(rebuild_due(list, c));
  c.position[17].x += 0.02e-3;
  EXPECT_TRUE(rebuild_due(list, c));
  c.position[17].x -= 0.02e-3;
  c.position[18].x += 0.51e-3;
  EXPECT_TRUE(rebuild_due(list, c));
}

// A list's bytes (as saved: version 4) in the format of version 3: with an index of the pairs
// by second element (CSR offsets, then pair indices) before the elements' ids at the end.
std::string version_3_bytes(const NeighborList& list, const std::string& v4, std::size_t n) {
  std::vector<std::uint32_t> start(n + 1, 0), as_second;
  for (std::size_t p = 0; p < list.pairs(); ++p) ++start[list.second(p) + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  for (std::size_t e = 0; e < n; ++e) {
    for (std::size_t p = 0; p < list.pairs(); ++p) {
      if (list.second(p) == e) as_second.push_back(static_cast<std::uint32_t>(p));
    }
  }
  io::BinaryWriter index;
  index.put(start);
  index.put(as_second);
  std::string v3 = v4;
  v3.insert(v4.size() - (sizeof(std::uint64_t) + n * sizeof(std::uint32_t)), index.bytes());
  return v3;
}

// A list's bytes in the format of version 3 in that of version 2: each pair's stable
// identity after the second elements, and not the elements' ids at the build (`id`) at the end.
std::string version_2_bytes(const NeighborList& list, const std::string& v3, const std::vector<std::uint32_t>& id) {
  const std::size_t n = id.size(), count = sizeof(std::uint64_t);
  const std::size_t second_end = sizeof(double) + sizeof(int) + count + (count + n * sizeof(Vec3)) +
                                 (count + n * sizeof(double)) + 2 * (count + list.pairs() * sizeof(std::uint32_t));
  std::vector<std::uint64_t> key;
  for (std::size_t p = 0; p < list.pairs(); ++p) {
    const std::uint64_t a = id[list.first(p)], b = id[list.second(p)];
    key.push_back(std::min(a, b) << 32 | std::max(a, b));
  }
  io::BinaryWriter keys;
  keys.put(key);
  std::string v2 = v3.substr(0, v3.size() - (count + n * sizeof(std::uint32_t)));
  v2.insert(second_end, keys.bytes());
  return v2;
}

// A list saved with margins comes back with them; one of the first format (no margins) with
// half the skin for every element.
TEST(NeighborList, MarginsSurviveACheckpoint) {
  const Cloud c = random_cloud(300, 8);
  std::vector<double> margin(c.position.size(), 0.2e-3);
  margin[5] = 0.7e-3;
  NeighborList list(0.4e-3, 3);
  list.build(c.position, c.radius, c.owner, c.id, margin);
  io::BinaryWriter out;
  list.save(out);
  NeighborList back(1.0, 0);
  io::BinaryReader in(out.bytes(), "list");
  back.load(in, 4);
  EXPECT_TRUE(in.done());
  EXPECT_EQ(listed(back), listed(list));
  EXPECT_DOUBLE_EQ(back.margin(5), 0.7e-3);
  EXPECT_DOUBLE_EQ(back.margin(6), 0.2e-3);
  // Version 3 kept an index of the pairs by second element, which loading skips.
  NeighborList back3(1.0, 0);
  const std::string v3_bytes = version_3_bytes(list, out.bytes(), c.position.size());
  io::BinaryReader in3(v3_bytes, "list");
  back3.load(in3, 3);
  EXPECT_TRUE(in3.done());
  EXPECT_EQ(listed(back3), listed(list));
  // The first format: the same fields without the margins (skin, history size, builds and
  // the reference positions come before them).
  NeighborList uniform(0.4e-3, 3);
  uniform.build(c.position, c.radius, c.owner, c.id);
  io::BinaryWriter v4;
  uniform.save(v4);
  const std::size_t at = sizeof(double) + sizeof(int) + 2 * sizeof(std::uint64_t) + c.position.size() * sizeof(Vec3);
  std::string v1 = version_2_bytes(uniform, version_3_bytes(uniform, v4.bytes(), c.position.size()), c.id);
  v1.erase(at, sizeof(std::uint64_t) + c.position.size() * sizeof(double));
  NeighborList old(1.0, 0);
  io::BinaryReader in1(v1, "list");
  old.load(in1, 1);
  EXPECT_TRUE(in1.done());
  EXPECT_EQ(listed(old), listed(uniform));
  for (std::size_t e = 0; e < c.position.size(); ++e) ASSERT_EQ(old.margin(e), 0.2e-3);
}

// A saved list whose pair names an element that is not there is damage, not a crash later.
TEST(NeighborList, ACheckpointWithAnIndexOutOfRangeIsDamage) {
  const Cloud c = random_cloud(300, 8);
  NeighborList list(0.4e-3, 3);
  list.build(c.position, c.radius, c.owner, c.id);
  io::BinaryWriter out;
  list.save(out);
  const std::size_t n = c.position.size(), count = sizeof(std::uint64_t);
  const std::size_t second_at = sizeof(double) + sizeof(int) + count + (count + n * sizeof(Vec3)) +
                                (count + n * sizeof(double)) + (count + list.pairs() * sizeof(std::uint32_t)) + count;
  std::string bytes = out.bytes();
  bytes.replace(second_at, sizeof(std::uint32_t), std::string(sizeof(std::uint32_t), '\xff'));
  NeighborList back(1.0, 0);
  io::BinaryReader in(bytes, "list");
  try {
    back.load(in, 4);
    FAIL() << "loaded a pair with an element out of range";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("index out of range"), std::string::npos) << e.what();
  }
}

TEST(NeighborList, PairsGroupedByFirstWithTheHigherElementSecond) {
  const Cloud c = random_cloud(300, 7);
  NeighborList list(0.4e-3, 0);
  list.build(c.position, c.radius, c.owner, c.id);
  EXPECT_EQ(list.begin_of(0), 0u);
  EXPECT_EQ(list.begin_of(c.position.size()), list.pairs());
  for (std::size_t e = 0; e < c.position.size(); ++e) {
    for (std::size_t p = list.begin_of(e); p < list.begin_of(e + 1); ++p) {
      EXPECT_EQ(list.first(p), e);
      EXPECT_GT(list.second(p), e);
      if (p > list.begin_of(e)) {
        EXPECT_LT(list.second(p - 1), list.second(p));
      }
    }
  }
}

TEST(NeighborList, HistorySurvivesRebuildAndRenumbering) {
  Cloud c = random_cloud(600, 11);
  NeighborList list(0.4e-3, 3);
  list.build(c.position, c.radius, c.owner, c.id);
  // Tag each pair's history with its stable identity.
  std::map<std::pair<std::uint32_t, std::uint32_t>, double> tag;
  for (std::size_t p = 0; p < list.pairs(); ++p) {
    const double v = 1.0 + static_cast<double>(p);
    list.history(p)[0] = v;
    list.history(p)[2] = -v;
    tag[{c.id[list.first(p)], c.id[list.second(p)]}] = v;
  }
  // Reverse the array order (as a spatial sort would) and move everything a little.
  Cloud r;
  for (std::size_t i = c.position.size(); i-- > 0;) {
    r.position.push_back(c.position[i] + Vec3{1e-5, 0, 0});
    r.radius.push_back(c.radius[i]);
    r.owner.push_back(c.owner[i]);
    r.id.push_back(c.id[i]);
  }
  list.build(r.position, r.radius, r.owner, r.id);
  std::size_t carried = 0;
  for (std::size_t p = 0; p < list.pairs(); ++p) {
    std::uint32_t a = r.id[list.first(p)], b = r.id[list.second(p)];
    if (a > b) std::swap(a, b);
    const auto it = tag.find({a, b});
    if (it == tag.end()) {
      EXPECT_EQ(list.history(p)[0], 0.0);  // a new pair starts from zero
    } else {
      EXPECT_EQ(list.history(p)[0], it->second);
      EXPECT_EQ(list.history(p)[2], -it->second);
      ++carried;
    }
  }
  EXPECT_GT(carried, list.pairs() / 2);
}

// Between renumberings a rebuild merges each element's old and new partners by index, also
// after a restart (the list keeps the ids it was built with); after a renumbering, or a
// restart from a list of version 2 (which kept each pair's stable identity instead), it looks
// each pair up by stable identity. All must carry the same histories, and the merge must keep
// exactly the pairs found again.
TEST(NeighborList, HistoryMergedInPlaceAsByLookup) {
  Cloud c = random_cloud(900, 13);
  NeighborList merged(0.4e-3, 2);
  merged.build(c.position, c.radius, c.owner, c.id);
  std::map<std::pair<std::uint32_t, std::uint32_t>, double> tag;
  for (std::size_t p = 0; p < merged.pairs(); ++p) {
    const double v = (p % 3 == 0) ? 0.0 : 1.0 + static_cast<double>(p);  // some contacts ended (zero)
    merged.history(p)[0] = v;
    merged.history(p)[1] = 2.0 * v;
    tag[{merged.first(p), merged.second(p)}] = v;
  }
  io::BinaryWriter out;
  merged.save(out);
  NeighborList restored(1.0, 0), looked_up(1.0, 0);
  io::BinaryReader in(out.bytes(), "list");
  restored.load(in, 4);
  const std::string v2 = version_2_bytes(merged, version_3_bytes(merged, out.bytes(), c.position.size()), c.id);
  io::BinaryReader in2(v2, "list");
  looked_up.load(in2, 2);  // it does not know the ids it was built with
  EXPECT_TRUE(in.done() && in2.done());
  // Move every element by up to a skin, so that pairs both leave the list and join it.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.4e-3, 0.4e-3);
  for (Vec3& x : c.position) x += Vec3{u(rng), u(rng), u(rng)};
  merged.build(c.position, c.radius, c.owner, c.id);
  looked_up.build(c.position, c.radius, c.owner, c.id);
  restored.build(c.position, c.radius, c.owner, c.id);
  ASSERT_EQ(merged.pairs(), looked_up.pairs());
  ASSERT_EQ(merged.pairs(), restored.pairs());
  for (std::size_t p = 0; p < merged.pairs(); ++p) ASSERT_EQ(merged.history(p)[1], restored.history(p)[1]);
  std::size_t kept = 0, joined = 0;
  for (std::size_t p = 0; p < merged.pairs(); ++p) {
    ASSERT_EQ(merged.first(p), looked_up.first(p));
    ASSERT_EQ(merged.second(p), looked_up.second(p));
    EXPECT_EQ(merged.history(p)[0], looked_up.history(p)[0]);
    EXPECT_EQ(merged.history(p)[1], looked_up.history(p)[1]);
    const auto it = tag.find({merged.first(p), merged.second(p)});
    const double expected = it == tag.end() ? 0.0 : it->second;
    EXPECT_EQ(merged.history(p)[0], expected);
    EXPECT_EQ(merged.history(p)[1], 2.0 * expected);
    (it == tag.end() ? joined : kept) += 1;
  }
  EXPECT_GT(kept, 100u);
  EXPECT_GT(joined, 10u);
  EXPECT_LT(kept, tag.size());  // some pairs left the list
}

TEST(NeighborList, RebuildOnlyAfterHalfTheSkin) {
  Cloud c = random_cloud(50, 5);
  NeighborList list(1e-3, 0);
  auto due = [&] { return rebuild_due(list, c); };
  EXPECT_TRUE(due());
  list.build(c.position, c.radius, c.owner, c.id);
  EXPECT_FALSE(due());
  c.position[17].x += 0.49e-3;
  EXPECT_FALSE(due());
  c.position[17].x += 0.02e-3;
  EXPECT_TRUE(due());
  c.position[17].x -= 0.02e-3;
  c.position.push_back(c.position[3]);  // an element added since the build
  EXPECT_TRUE(due());
}

}  // namespace
}  // namespace bushel
