#!/bin/bash
# benchmarks/planner_counts.sh, run from the repository root (issue 42 item 2 and 3 counts).
# count.sh: in the current tree, (1) code lines outside the planner table that hold a planner
# name as a string literal (each is a name comparison or a name-keyed lookup);
# (doc comments and the table's own files left out); (2) io/view headers that include planning's algorithm headers.
N='"(astar|astar-euclid|astar-coarse|rrtconnect|rrtstar|informed-rrtstar|bitstar|abitstar|aitstar|prmstar|lazyprmstar|fmtstar|AStar|AStarEuclid|AStarCoarse|RRTConnect|RRTstar|InformedRRTstar|BITstar|ABITstar|AITstar|PRMstar|LazyPRMstar|FMT)"'
echo "name literals outside the table:"
grep -rnE "$N" src planners include | grep -vE "^[^:]+:[0-9]+:.*//.*$N" | grep -vE 'planner_table\.(cpp|h)' | grep -v 'planner{"astar-coarse"}'
echo "count: $(grep -rnE "$N" src planners include | grep -vE "^[^:]+:[0-9]+:.*//.*$N" | grep -vE 'planner_table\.(cpp|h)' | grep -v 'planner{"astar-coarse"}' | wc -l)"
echo "table rows: $(grep -cE "$N" planners/planner_table.cpp src/planning/planner_table.cpp 2>/dev/null | tr '\n' ' ')"
echo "io/view headers including planning algorithm headers:"
grep -lE 'planning/(flight_planner|mission_planner|path_validator|planner|path_simplifier|tour|path_join)\.h' include/uavip/io/*.h include/uavip/view/*.h
echo "count: $(grep -lE 'planning/(flight_planner|mission_planner|path_validator|planner|path_simplifier|tour|path_join)\.h' include/uavip/io/*.h include/uavip/view/*.h | wc -l)"
echo "app scenario/config headers including planners/ or planning algorithm headers: $(grep -lE '#include .*(planners/|planning/(flight_planner|mission_planner|planner)\.h)' include/uavip/app/scenario.h include/uavip/app/config.h | wc -l)"
