#include "planners/astar.h"

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <future>
#include <iterator>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <queue>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "uavip/core/error.h"

namespace uavip::planners {

namespace {

/// Grids up to this many voxels use a dense scratch (12 B a voxel of address space,
/// laid out in tiles (TileLayout), kept in a pool every thread borrows from and reused by every
/// search on a grid of the same size; zero pages, so only the pages a search touches cost memory
/// and time: a search costs O(expansions), not O(grid)); larger grids use a hash map so memory
/// stays bounded.
constexpr std::size_t kDenseScratchLimit = 16'000'000;

constexpr std::uint8_t kNoParent = 255;

/// A dense scratch gives its pages back once searches have written this many bytes
/// of them (DenseStore::release).
constexpr std::size_t kResidentBytes = std::size_t{64} << 20;

struct Move {
  int dx, dy, dz;
  double cost;
};

/// One open-list entry. Ordered by f, then larger g, then smaller linear index.
struct OpenEntry {
  double f;
  double g;
  std::size_t idx;
};

struct WorseEntry {
  bool operator()(const OpenEntry& a, const OpenEntry& b) const {
    if (a.f != b.f) return a.f > b.f;
    if (a.g != b.g) return a.g < b.g;
    return a.idx > b.idx;
  }
};

/// Per-voxel search state: g-score, parent move (0..25 or kNoParent), closed flag.
struct NodeState {
  double g{std::numeric_limits<double>::infinity()};
  std::uint8_t parent{kNoParent};
  bool closed{false};
};

/// An array of n zero-initialised T from calloc: a large block comes from the OS as
/// untouched zero pages, so a search that visits a few voxels of a big grid faults
/// in a few pages instead of writing the whole array.
template <typename T>
class ZeroedArray {
 public:
  ZeroedArray() = default;
  ZeroedArray(const ZeroedArray&) = delete;
  ZeroedArray& operator=(const ZeroedArray&) = delete;
  ~ZeroedArray() { std::free(data_); }
  void reset(std::size_t n) {
    std::free(data_);
    data_ = nullptr;
    size_ = 0;
    if (n == 0) return;
    data_ = static_cast<T*>(std::calloc(n, sizeof(T)));
    if (data_ == nullptr) throw std::bad_alloc();
    size_ = n;
  }
  std::size_t size() const { return size_; }
  /// Gives the whole pages inside the array back to the OS; they read as zero again
  /// (anonymous memory), so the array stays zero-initialised where it was.
  void releasePages() {
    if (data_ == nullptr) return;
    const auto page = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
    char* const bytes = reinterpret_cast<char*>(data_);
    const std::size_t head = (page - reinterpret_cast<std::uintptr_t>(bytes) % page) % page;
    const std::size_t size = size_ * sizeof(T);
    const std::size_t whole = size > head ? (size - head) / page * page : 0;
    if (whole > 0) ::madvise(bytes + head, whole, MADV_DONTNEED);
  }
  T& operator[](std::size_t i) { return data_[i]; }
  const T& operator[](std::size_t i) const { return data_[i]; }

 private:
  T* data_{nullptr};
  std::size_t size_{0};
};

/// Dense scratch reused across searches; `stamp` tells which entries are current,
/// so a search touches only the voxels it reaches (no O(grid) reset). A voxel's
/// g-score, stamp (24 bits) and parent (8 bits) share one 12-byte cell (4-byte
/// aligned: the g-score's 8 bytes copied in and out), a quarter less memory than a
/// 16-byte aligned one for the pages a long search faults in.
///
/// Pages: a cell is read only on a page written since the last release (`written_`,
/// a byte a 4 KiB page); any other reads as unvisited without touching memory. So a
/// page's first touch is a write (one fault) rather than a read that maps the
/// kernel's zero page and a write that then replaces it (a second fault, and a TLB
/// flush on every core the process runs on). Once searches have written
/// kResidentBytes of pages, release() gives them back, so a scratch holds at most
/// that much plus one search, however many legs a flight searches on it.
struct DenseStore {
  struct Cell {
    std::uint32_t g[2];  ///< the g-score's bytes
    std::uint32_t tag;   ///< stamp << 8 | parent (bit 7: closed; low bits: move index)
  };
  static_assert(sizeof(Cell) == 12, "a 12-byte cell");
  static constexpr std::uint32_t kStamps = std::uint32_t{1} << 24;
  static constexpr std::size_t kPageBytes = 4096;  ///< pages counted in 4 KiB

  std::size_t size() const { return cells_.size(); }
  void begin(std::size_t n) {
    if (cells_.size() != n) {
      cells_.reset(n);
      written_.assign(n * sizeof(Cell) / kPageBytes + 1, 0);
      written_pages_ = 0;
      current_ = 0;
    }
    if (++current_ == kStamps) {  // wrapped: clear once
      cells_.reset(n);
      forgetPages();
      current_ = 1;
    }
  }
  /// After a search: the pages back to the OS once kResidentBytes are written.
  void release() {
    if (written_pages_ * kPageBytes < kResidentBytes) return;
    cells_.releasePages();
    forgetPages();
  }
  NodeState get(std::size_t i) const {
    if (written_[i * sizeof(Cell) / kPageBytes] == 0) return {};
    const Cell& c = cells_[i];
    if ((c.tag >> 8) != current_) return {};
    double g = 0.0;
    std::memcpy(&g, c.g, sizeof g);
    const auto bits = static_cast<std::uint8_t>(c.tag & 0x7F);
    return {g, bits == 0x7F ? kNoParent : bits, (c.tag & 0x80) != 0};
  }
  void set(std::size_t i, const NodeState& s) {
    std::uint8_t& w = written_[i * sizeof(Cell) / kPageBytes];
    written_pages_ += 1U - w;
    w = 1;
    Cell& c = cells_[i];
    std::memcpy(c.g, &s.g, sizeof s.g);
    c.tag = current_ << 8 | static_cast<std::uint32_t>((s.parent & 0x7F) | (s.closed ? 0x80 : 0));
  }

 private:
  void forgetPages() {
    std::fill(written_.begin(), written_.end(), std::uint8_t{0});
    written_pages_ = 0;
  }

  ZeroedArray<Cell> cells_;
  std::uint32_t current_{0};
  std::vector<std::uint8_t> written_;  ///< per page: written since the last release
  std::size_t written_pages_{0};
};

struct HashStore {
  std::unordered_map<std::size_t, NodeState> map;
  void begin(std::size_t /*n*/) { map.clear(); }
  NodeState get(std::size_t i) const {
    const auto it = map.find(i);
    return it == map.end() ? NodeState{} : it->second;
  }
  void set(std::size_t i, const NodeState& s) { map[i] = s; }
};

std::vector<Move> makeMoves(const AStarOptions& o) {
  std::vector<Move> moves;
  for (int dz = -1; dz <= 1; ++dz) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (dx == 0 && dy == 0 && dz == 0) continue;
        moves.push_back({dx, dy, dz, stepCost(dx, dy, dz, o)});
      }
    }
  }
  return moves;
}

double heuristic(const world::Index3& a, const world::Index3& b, const AStarOptions& o) {
  const double dx = std::abs(a.x - b.x);
  const double dy = std::abs(a.y - b.y);
  const double dz = std::abs(a.z - b.z);
  if (o.cost == AStarCost::Paper) return o.a1 * dx + o.a2 * dy + o.a3 * dz;
  return std::sqrt(o.a1 * dx * dx + o.a2 * dy * dy + o.a3 * dz * dz);
}

/// The fine grid as a search space.
struct FineSpace {
  const world::VoxelGrid& grid;
  bool isBlocked(const world::Index3& i) const { return grid.isBlocked(i); }
  std::size_t linear(const world::Index3& i) const { return grid.linear(i); }
  const std::array<int, 3>& dims() const { return grid.dims(); }
  std::size_t voxelCount() const { return grid.voxelCount(); }
};

/// Blocks of k×k×k voxels; a block is free when all of its voxels are free (and in
/// the grid), or, for an `optimistic` grid, when any of them is; `label` numbers the
/// 26-connected regions of free blocks (0: not free).
struct CoarseGrid {
  std::uint64_t content_id{0};
  int factor{0};
  bool optimistic{false};
  std::array<int, 3> dims{0, 0, 0};
  std::vector<std::uint8_t> free;
  std::vector<std::int32_t> label;

  bool inBounds(const world::Index3& i) const {
    return i.x >= 0 && i.y >= 0 && i.z >= 0 && i.x < dims[0] && i.y < dims[1] && i.z < dims[2];
  }
  std::size_t linear(const world::Index3& i) const {
    return static_cast<std::size_t>(i.x) +
           static_cast<std::size_t>(dims[0]) *
               (static_cast<std::size_t>(i.y) +
                static_cast<std::size_t>(dims[1]) * static_cast<std::size_t>(i.z));
  }
  world::Index3 blockOf(const world::Index3& i) const {
    return {i.x / factor, i.y / factor, i.z / factor};
  }
};

/// Numbers the 26-connected regions of free blocks (breadth first, in linear order).
void labelRegions(CoarseGrid& c) {
  c.label.assign(c.free.size(), 0);
  std::int32_t next = 0;
  std::vector<world::Index3> queue;
  for (int z = 0; z < c.dims[2]; ++z)
    for (int y = 0; y < c.dims[1]; ++y)
      for (int x = 0; x < c.dims[0]; ++x) {
        const std::size_t l0 = c.linear({x, y, z});
        if (c.free[l0] == 0 || c.label[l0] != 0) continue;
        c.label[l0] = ++next;
        queue.assign(1, {x, y, z});
        while (!queue.empty()) {
          const world::Index3 b = queue.back();
          queue.pop_back();
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const world::Index3 n{b.x + dx, b.y + dy, b.z + dz};
                if (!c.inBounds(n)) continue;
                const std::size_t l = c.linear(n);
                if (c.free[l] == 0 || c.label[l] != 0) continue;
                c.label[l] = next;
                queue.push_back(n);
              }
        }
      }
}

/// True when a block path can join the end blocks `s` and `g` (which count as free):
/// they touch, or some free block next to `s` lies in the region of one next to `g`.
/// Saves a coarse search that would fail after visiting a whole region.
bool blocksMayJoin(const CoarseGrid& c, const world::Index3& s, const world::Index3& g) {
  if (c.label.empty()) return true;  // optimistic: not labelled
  if (std::max({std::abs(s.x - g.x), std::abs(s.y - g.y), std::abs(s.z - g.z)}) <= 1) return true;
  const auto regions = [&c](const world::Index3& b) {
    std::vector<std::int32_t> out;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const world::Index3 n{b.x + dx, b.y + dy, b.z + dz};
          if (c.inBounds(n) && c.label[c.linear(n)] != 0) out.push_back(c.label[c.linear(n)]);
        }
    std::sort(out.begin(), out.end());
    return out;
  };
  const std::vector<std::int32_t> a = regions(s), b = regions(g);
  std::vector<std::int32_t> both;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(both));
  return !both.empty();
}

/// The blocks of `grid` (one pass over its voxels). An optimistic grid gets no
/// region labels: its free blocks join wherever free voxels do, and coarseToFine
/// has already checked the grid's own components.
void buildCoarse(CoarseGrid& c, const world::VoxelGrid& grid, int factor, bool optimistic) {
  const auto& d = grid.dims();
  c.content_id = grid.contentId();
  c.factor = factor;
  c.optimistic = optimistic;
  for (int a = 0; a < 3; ++a) c.dims[a] = (d[a] + factor - 1) / factor;
  c.free.assign(static_cast<std::size_t>(c.dims[0]) * static_cast<std::size_t>(c.dims[1]) *
                    static_cast<std::size_t>(c.dims[2]),
                optimistic ? 0 : 1);
  // A free voxel frees its optimistic block; a blocked one (voxels beyond the grid,
  // in a partial last block, count as blocked) closes its plain block.
  const std::uint8_t mark = optimistic ? 1 : 0;
  for (int z = 0; z < c.dims[2] * factor; ++z)
    for (int y = 0; y < c.dims[1] * factor; ++y) {
      std::uint8_t* blocks = c.free.data() + c.linear({0, y / factor, z / factor});
      if (z >= d[2] || y >= d[1]) {
        if (!optimistic) std::fill(blocks, blocks + c.dims[0], std::uint8_t{0});
        continue;
      }
      for (int x = 0; x < d[0]; ++x)
        if (grid.isBlocked({x, y, z}) != optimistic) blocks[x / factor] = mark;
      if (!optimistic && d[0] % factor != 0) blocks[c.dims[0] - 1] = 0;
    }
  if (optimistic) {
    c.label.clear();
  } else {
    labelRegions(c);
  }
}

/// The block grid as a search space; the blocks of the two ends count as free.
struct CoarseSpace {
  const CoarseGrid& coarse;
  std::size_t start, goal;  ///< linear indices of the end blocks
  bool isBlocked(const world::Index3& i) const {
    if (!coarse.inBounds(i)) return true;
    const std::size_t l = coarse.linear(i);
    return coarse.free[l] == 0 && l != start && l != goal;
  }
  std::size_t linear(const world::Index3& i) const { return coarse.linear(i); }
  const std::array<int, 3>& dims() const { return coarse.dims; }
  std::size_t voxelCount() const { return coarse.free.size(); }
};

/// The fine grid inside a corridor of blocks.
struct CorridorSpace {
  const world::VoxelGrid& grid;
  const std::vector<std::uint8_t>& corridor;  ///< per block: 1 = inside
  /// Per axis, a voxel coordinate's share of its block's linear index (no divisions
  /// in the search's inner loop).
  std::array<std::vector<std::size_t>, 3> block_part;

  CorridorSpace(const world::VoxelGrid& g, const CoarseGrid& coarse,
                const std::vector<std::uint8_t>& c)
      : grid(g), corridor(c) {
    const std::array<std::size_t, 3> stride{
        1, static_cast<std::size_t>(coarse.dims[0]),
        static_cast<std::size_t>(coarse.dims[0]) * static_cast<std::size_t>(coarse.dims[1])};
    for (int a = 0; a < 3; ++a) {
      auto& part = block_part[static_cast<std::size_t>(a)];
      part.resize(static_cast<std::size_t>(g.dims()[static_cast<std::size_t>(a)]));
      for (std::size_t v = 0; v < part.size(); ++v)
        part[v] =
            (v / static_cast<std::size_t>(coarse.factor)) * stride[static_cast<std::size_t>(a)];
    }
  }
  bool isBlocked(const world::Index3& i) const {
    if (grid.isBlocked(i)) return true;  // also every voxel outside the grid
    return corridor[block_part[0][static_cast<std::size_t>(i.x)] +
                    block_part[1][static_cast<std::size_t>(i.y)] +
                    block_part[2][static_cast<std::size_t>(i.z)]] == 0;
  }
  std::size_t linear(const world::Index3& i) const { return grid.linear(i); }
  const std::array<int, 3>& dims() const { return grid.dims(); }
  std::size_t voxelCount() const { return grid.voxelCount(); }
};

/// The search state's slot of a voxel: the grid in tiles of 8 × 8 × 8 voxels, each
/// tile's 512 slots together (6 KiB of 12-byte cells). A search's compact region then
/// writes a page or two per tile it reaches instead of a page per x-row it crosses
/// (a 50³-voxel region: about 500 pages, not 2,500), which bounds the dense scratch's
/// resident memory and its page faults. The open list still orders ties by the
/// grid's linear index, so paths do not depend on the layout.
struct TileLayout {
  static constexpr int kShift = 3;  ///< 8 voxels a side
  static constexpr int kMask = (1 << kShift) - 1;
  std::size_t tiles_x{0}, tiles_y{0}, slots{0};

  explicit TileLayout(const std::array<int, 3>& dims) {
    const auto tiles = [](int n) { return (static_cast<std::size_t>(n) + kMask) >> kShift; };
    tiles_x = tiles(dims[0]);
    tiles_y = tiles(dims[1]);
    slots = (tiles_x * tiles_y * tiles(dims[2])) << (3 * kShift);
  }
  std::size_t of(const world::Index3& i) const {
    const std::size_t tile = (static_cast<std::size_t>(i.z >> kShift) * tiles_y +
                              static_cast<std::size_t>(i.y >> kShift)) *
                                 tiles_x +
                             static_cast<std::size_t>(i.x >> kShift);
    return tile << (3 * kShift) | static_cast<std::size_t>((i.z & kMask) << (2 * kShift) |
                                                           (i.y & kMask) << kShift | (i.x & kMask));
  }
};

template <typename Store, typename Space>
GridSearchResult search(Store& store, const Space& grid, const world::Index3& start,
                        const world::Index3& goal, const AStarOptions& options) {
  GridSearchResult result;
  if (grid.isBlocked(start) || grid.isBlocked(goal)) return result;
  const std::vector<Move> moves = makeMoves(options);
  const auto& dims = grid.dims();
  const TileLayout slots(dims);
  store.begin(slots.slots);

  std::priority_queue<OpenEntry, std::vector<OpenEntry>, WorseEntry> open;
  const std::size_t start_idx = grid.linear(start);
  const std::size_t goal_idx = grid.linear(goal);
  store.set(slots.of(start), {0.0, kNoParent, false});
  open.push({heuristic(start, goal, options), 0.0, start_idx});

  auto toIndex3 = [&dims](std::size_t i) {
    const std::size_t nx = static_cast<std::size_t>(dims[0]);
    const std::size_t ny = static_cast<std::size_t>(dims[1]);
    return world::Index3{static_cast<int>(i % nx), static_cast<int>((i / nx) % ny),
                         static_cast<int>(i / (nx * ny))};
  };

  while (!open.empty()) {
    const OpenEntry top = open.top();
    open.pop();
    const world::Index3 c = toIndex3(top.idx);
    const std::size_t slot = slots.of(c);
    NodeState s = store.get(slot);
    if (s.closed || top.g > s.g) continue;  // stale entry
    s.closed = true;
    store.set(slot, s);
    if (top.idx == goal_idx) {
      result.found = true;
      result.cost = s.g;
      // Walk the parent moves back to the start.
      world::Index3 at = goal;
      result.cells.push_back(at);
      std::uint8_t p = s.parent;
      while (p != kNoParent) {
        const Move& m = moves[p];
        at = {at.x - m.dx, at.y - m.dy, at.z - m.dz};
        result.cells.push_back(at);
        p = store.get(slots.of(at)).parent;
      }
      std::reverse(result.cells.begin(), result.cells.end());
      return result;
    }
    if (options.max_expansions > 0 && result.expansions >= options.max_expansions) {
      result.exhausted_budget = true;
      return result;
    }
    ++result.expansions;
    for (std::size_t m = 0; m < moves.size(); ++m) {
      const world::Index3 n{c.x + moves[m].dx, c.y + moves[m].dy, c.z + moves[m].dz};
      if (grid.isBlocked(n)) continue;
      const std::size_t n_slot = slots.of(n);
      const NodeState ns = store.get(n_slot);
      if (ns.closed) continue;
      const double g = s.g + moves[m].cost;
      if (g < ns.g) {
        store.set(n_slot, {g, static_cast<std::uint8_t>(m), false});
        open.push({g + heuristic(n, goal, options), g, grid.linear(n)});
      }
    }
  }
  return result;
}

}  // namespace

double stepCost(int dx, int dy, int dz, const AStarOptions& options) {
  const double c = options.a1 * dx * dx + options.a2 * dy * dy + options.a3 * dz * dz;
  return options.cost == AStarCost::Paper ? c : std::sqrt(c);
}

namespace {

/// Dense scratches shared by all threads. A search borrows one of its space's size
/// (else a new one) and gives it back, so a search on a fresh thread (a
/// parallelFor worker, the flight's thread) reuses pages an earlier search already
/// faulted in instead of faulting in a scratch of its own. At most kPoolKeep
/// scratches are kept; the stamps make a borrowed scratch as good as a new one.
class ScratchPool {
 public:
  std::unique_ptr<DenseStore> take(std::size_t n) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto it =
        std::find_if(kept_.begin(), kept_.end(), [n](const auto& s) { return s->size() == n; });
    if (it == kept_.end()) return std::make_unique<DenseStore>();
    std::unique_ptr<DenseStore> s = std::move(*it);
    kept_.erase(it);
    return s;
  }
  void clear() {
    const std::lock_guard<std::mutex> lock(mutex_);
    kept_.clear();
  }
  void give(std::unique_ptr<DenseStore> s) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (kept_.size() >= kPoolKeep) kept_.erase(kept_.begin());  // the least recently given
    kept_.push_back(std::move(s));
  }

 private:
  static constexpr std::size_t kPoolKeep = 8;  ///< the fine grid and three block sizes, two cores
  std::mutex mutex_;
  std::vector<std::unique_ptr<DenseStore>> kept_;
};

ScratchPool& scratchPool() {
  static ScratchPool pool;
  return pool;
}

/// A* on `space` with a dense scratch borrowed from the pool, or a hash map on large
/// grids.
template <typename Space>
GridSearchResult searchSpace(const Space& space, const world::Index3& start,
                             const world::Index3& goal, const AStarOptions& options) {
  const std::size_t slots = TileLayout(space.dims()).slots;
  if (space.voxelCount() <= kDenseScratchLimit && slots <= 2 * kDenseScratchLimit) {
    std::unique_ptr<DenseStore> dense = scratchPool().take(slots);
    GridSearchResult r = search(*dense, space, start, goal, options);
    dense->release();
    scratchPool().give(std::move(dense));
    return r;
  }
  HashStore hash;
  return search(hash, space, start, goal, options);
}

}  // namespace

void releaseSearchScratch() { scratchPool().clear(); }

namespace {

/// Takes `spent` expansions off o's budget; false when nothing is left (a budget of 0
/// means unlimited, so a spent budget must not become 0).
bool spendBudget(AStarOptions& o, std::size_t spent) {
  if (o.max_expansions == 0) return true;
  if (spent >= o.max_expansions) return false;
  o.max_expansions -= spent;
  return true;
}

/// The blocks of `grid` at `factor`, built once per grid content, factor and kind,
/// and shared by every thread (read only once built). The lock covers only the
/// lookup: a thread that asks for blocks another one is building waits for those,
/// not for every build. The cache keeps the kCoarseKeep latest requested (content,
/// factor, kind); a caller's shared pointer keeps its blocks alive while it searches.
std::shared_ptr<const CoarseGrid> coarseGrid(const world::VoxelGrid& grid, int factor,
                                             bool optimistic) {
  using Blocks = std::shared_future<std::shared_ptr<const CoarseGrid>>;
  struct Entry {
    std::uint64_t content_id;
    int factor;
    bool optimistic;
    Blocks blocks;
  };
  constexpr std::size_t kCoarseKeep = 12;  // two grids' six levels
  static std::mutex mutex;
  static std::vector<Entry> cache;  // latest used last
  const auto same = [&](const Entry& e) {
    return e.content_id == grid.contentId() && e.factor == factor && e.optimistic == optimistic;
  };
  std::promise<std::shared_ptr<const CoarseGrid>> built;
  Blocks blocks;
  bool build = false;
  {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto it = std::find_if(cache.begin(), cache.end(), same);
    Entry entry{grid.contentId(), factor, optimistic, {}};
    if (it != cache.end()) {
      entry = *it;
      cache.erase(it);
    } else {
      entry.blocks = built.get_future().share();
      build = true;
      if (cache.size() >= kCoarseKeep) cache.erase(cache.begin());
    }
    blocks = entry.blocks;
    cache.push_back(std::move(entry));
  }
  if (build) {
    try {
      auto grid_blocks = std::make_shared<CoarseGrid>();
      buildCoarse(*grid_blocks, grid, factor, optimistic);
      built.set_value(std::move(grid_blocks));
    } catch (...) {  // e.g. bad_alloc: the next asker builds again
      {
        const std::lock_guard<std::mutex> lock(mutex);
        cache.erase(std::remove_if(cache.begin(), cache.end(), same), cache.end());
      }
      built.set_exception(std::current_exception());
    }
  }
  return blocks.get();
}

/// One level of coarse to fine: the block path at `factor`, then the fine search in
/// its corridor. found = false (expansions counted) when either finds nothing.
GridSearchResult corridorSearch(const world::VoxelGrid& grid, int factor, bool optimistic,
                                const world::Index3& start, const world::Index3& goal,
                                const AStarOptions& options) {
  const std::shared_ptr<const CoarseGrid> blocks_of_grid = coarseGrid(grid, factor, optimistic);
  const CoarseGrid& coarse = *blocks_of_grid;
  const world::Index3 s = coarse.blockOf(start), g = coarse.blockOf(goal);
  if (!blocksMayJoin(coarse, s, g)) return {};
  GridSearchResult blocks =
      searchSpace(CoarseSpace{coarse, coarse.linear(s), coarse.linear(g)}, s, g, options);
  if (!blocks.found) return blocks;
  std::vector<std::uint8_t> corridor(coarse.free.size(), 0);
  for (const world::Index3& b : blocks.cells)
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const world::Index3 n{b.x + dx, b.y + dy, b.z + dz};
          if (coarse.inBounds(n)) corridor[coarse.linear(n)] = 1;
        }
  AStarOptions fine = options;
  if (!spendBudget(fine, blocks.expansions)) return {false, {}, 0.0, blocks.expansions, true};
  GridSearchResult r = searchSpace(CorridorSpace(grid, coarse, corridor), start, goal, fine);
  r.expansions += blocks.expansions;
  return r;
}

/// Coarse to fine (astar.h): blocks of coarse_factor, then of half as many voxels
/// and so on down to 2 (a passage too narrow for one level may fit the next), then
/// the same factors again with blocks that count as free when any of their voxels is
/// (a passage one voxel wide; such a block path may hold no fine path, and the
/// corridor search then fails), then the whole grid.
GridSearchResult coarseToFine(const world::VoxelGrid& grid, const world::Index3& start,
                              const world::Index3& goal, const AStarOptions& options) {
  // The 26 moves join exactly the grid's 26-connected components.
  if (grid.isBlocked(start) || grid.isBlocked(goal) || !grid.connected(start, goal)) return {};
  std::size_t spent = 0;
  std::vector<std::pair<int, bool>> levels;
  for (int factor = options.coarse_factor; factor >= 2; factor /= 2)
    levels.push_back({factor, false});
  for (int factor = options.coarse_factor; factor >= 2; factor /= 2)
    levels.push_back({factor, true});
  for (const auto& [factor, optimistic] : levels) {
    AStarOptions level = options;
    if (!spendBudget(level, spent)) return {false, {}, 0.0, spent, true};
    GridSearchResult r = corridorSearch(grid, factor, optimistic, start, goal, level);
    r.expansions += spent;
    if (r.found || r.exhausted_budget) return r;
    spent = r.expansions;
  }
  AStarOptions whole = options;
  if (!spendBudget(whole, spent)) return {false, {}, 0.0, spent, true};
  GridSearchResult r = searchSpace(FineSpace{grid}, start, goal, whole);
  r.expansions += spent;
  return r;
}

}  // namespace

GridSearchResult astarSearch(const world::VoxelGrid& grid, const world::Index3& start,
                             const world::Index3& goal, const AStarOptions& options) {
  if (options.coarse_factor >= 2) return coarseToFine(grid, start, goal, options);
  return searchSpace(FineSpace{grid}, start, goal, options);
}

AStarPlanner::AStarPlanner(AStarOptions options, std::string name)
    : options_(options), name_(std::move(name)) {
  options_.validate("planner");
}

planning::PathResult AStarPlanner::plan(const world::VoxelGrid& grid, const Vec3& start,
                                        const Vec3& goal) {
  return planning::timedPlan(grid, start, goal, [&](planning::PathResult& out) {
    const world::Index3 s = grid.indexOf(start);
    const world::Index3 g = grid.indexOf(goal);
    if (s == g) {
      out.path = {start, goal};
      return;
    }
    const GridSearchResult r = astarSearch(grid, s, g, options_);
    out.expansions = r.expansions;
    if (!r.found) {
      out.status =
          r.exhausted_budget ? planning::PathStatus::Timeout : planning::PathStatus::NoPath;
      return;
    }
    out.cost = r.cost;
    // Exact start, centres of the intermediate cells, exact goal. A step between
    // adjacent free centres keeps the clearance (voxel_grid.h); the exact ends are
    // joined directly only when the segment crosses free voxels only, otherwise
    // through their own voxel's centre.
    const std::size_t n = r.cells.size();
    const Vec3 first_centre = grid.centreOf(r.cells.front());
    const Vec3 last_centre = grid.centreOf(r.cells.back());
    out.path.reserve(n + 2);
    out.path.push_back(start);
    const Vec3 after_start = n > 2 ? grid.centreOf(r.cells[1]) : goal;
    if (start != first_centre && !grid.segmentFree(start, after_start))
      out.path.push_back(first_centre);
    for (std::size_t i = 1; i + 1 < n; ++i) out.path.push_back(grid.centreOf(r.cells[i]));
    if (goal != last_centre && !grid.segmentFree(out.path.back(), goal))
      out.path.push_back(last_centre);
    out.path.push_back(goal);
  });
}

}  // namespace uavip::planners
