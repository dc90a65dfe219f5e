// The OMiCroN oracles on a finished hierarchy, and byte equality of two hierarchies (tests of host/core/points/).
#pragma once
#include "megavox/points.h"

namespace mv::test {

// Every node, column and count equal.
void expect_same(const PointHierarchy& a, const PointHierarchy& b);

// Without a reference: the root's code; each node's points lie in its cell (levels consistent with Morton
// prefixes); children's codes extend their parent's and their subtree counts add up; an inner node's
// representatives are copies of points in its subtree; the leaves hold every input point exactly once.
void expect_valid(const PointHierarchy& h, const PointColumns& input);

}  // namespace mv::test
