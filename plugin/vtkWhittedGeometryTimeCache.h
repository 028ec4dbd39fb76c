/**
 * @class   vtkWhittedGeometryTimeCache
 * @brief   internal: earlier contents of geometries, by fingerprint, kept outside the scene
 *
 * Private to the Whitted module: the time cache of vtkWhittedGeometryCache (its class
 * documentation says what is kept and why), which moves a geometry's scene objects in when its
 * contents are replaced and back out on a hit. This class holds those entries, with their BVHs,
 * under the fingerprints of the contents (vtkWhittedGeometryFingerprint), and applies the policy:
 * - WorthKeeping: contents are kept if they were a time step the time has moved on from, or if
 *   the same contents had been shown and replaced before (a re-shown input). The fingerprints of
 *   replaced contents are remembered for that (the last SeenLimit, not their geometry).
 * - Insert: an entry is kept within the memory limit (SetLimit) and only while a tenth of the
 *   machine's memory stays available; least recently used entries are dropped first.
 * - RemoveOtherMappers: kept contents (and remembered fingerprints) go with their mapper.
 *
 * @sa vtkWhittedGeometryCache vtkWhittedGeometryFingerprint
 */

#ifndef vtkWhittedGeometryTimeCache_h
#define vtkWhittedGeometryTimeCache_h

#include "vtkWhittedGeometryCache.h" // for Geometry, Options

#include "scene/scene.h" // for whitted::Object, whitted::Texture

#include <cstddef> // for std::size_t
#include <cstdint> // for uint64_t
#include <map>     // for std::map
#include <set>     // for std::set
#include <utility> // for std::pair
#include <vector>  // for std::vector

class vtkMapper;

class vtkWhittedGeometryTimeCache
{
public:
  /// Which contents: the geometry's mapper and options, and the fingerprints of the mapper state
  /// and of the input's contents.
  struct Key
  {
    vtkMapper* Mapper;
    vtkWhittedPolyDataConverter::Options Options;
    uint64_t State, Content;
    bool operator<(const Key& o) const;
  };

  /// Kept contents: the objects (with their BVHs) and what the geometry said about them.
  struct Entry
  {
    std::vector<std::pair<int, whitted::Object>> Objects; ///< (kind, object)
    /// What the geometry said about these objects (its object ids are unused).
    vtkWhittedGeometryCache::Geometry Info;
    whitted::Texture ColorMap; ///< The colour map the mesh's colour coordinates refer to.
    std::size_t Bytes = 0;     ///< Memory of the objects (geometry and BVHs).
    unsigned long LastUse = 0;
  };

  /// Starts a frame (the hit count is per frame).
  void BeginFrame() { this->Hits = 0; }

  /// Memory the entries may hold, bytes (0: none); entries beyond it are dropped.
  void SetLimit(std::size_t bytes);
  std::size_t GetLimit() const { return this->Limit; }

  /// Whether contents of key, which had the time (hasTime, time), are worth keeping now that
  /// contents of the time (nextHasTime, nextTime) replace them. Notes key as replaced.
  bool WorthKeeping(const Key& key, bool hasTime, double time, bool nextHasTime, double nextTime);

  /// Keeps entry under key, unless it does not fit (then it is dropped, its objects freed).
  void Insert(const Key& key, Entry entry);

  /// Moves the entry of key out of the cache into entry; false if there is none.
  bool Take(const Key& key, Entry& entry);

  /// Counts a hit: an entry taken and restored in this frame.
  void CountHit() { ++this->Hits; }

  /// Drops the entries and remembered fingerprints of every mapper not in used.
  void RemoveOtherMappers(const std::set<vtkMapper*>& used);

  /// Drops everything (the limit stays).
  void Clear();

  int GetHits() const { return this->Hits; }
  int GetNumberOfEntries() const { return static_cast<int>(this->Entries.size()); }
  std::size_t GetBytes() const { return this->Bytes; }

private:
  // Notes that the contents of key were shown and replaced; true if they had been before.
  bool SeenBefore(const Key& key);
  // Drops least recently used entries until within the limit (and the machine's memory).
  void Trim();

  std::map<Key, Entry> Entries;
  std::size_t Bytes = 0;
  std::size_t Limit = 0;
  unsigned long Uses = 0;
  int Hits = 0;
  // Fingerprints of contents shown and replaced (not their geometry), by last use: a contents
  // seen here again is a re-shown input, kept the next time it is replaced
  static constexpr std::size_t SeenLimit = 4096;
  std::map<Key, unsigned long> Seen;
};

#endif
// VTK-HeaderTest-Exclude: vtkWhittedGeometryTimeCache.h
