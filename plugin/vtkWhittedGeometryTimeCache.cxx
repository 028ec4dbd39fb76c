#include "vtkWhittedGeometryTimeCache.h"

#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <tuple>

namespace
{
//------------------------------------------------------------------------------
// Whether the machine keeps a tenth of its memory available after `extra` more bytes are used
// (Linux's MemAvailable; true where it cannot be read).
bool MemoryAllows(std::size_t extra)
{
  std::ifstream meminfo("/proc/meminfo");
  std::string name;
  std::size_t kb = 0, total = 0, available = std::numeric_limits<std::size_t>::max();
  while (meminfo >> name >> kb)
  {
    if (name == "MemTotal:")
    {
      total = kb * 1024;
    }
    else if (name == "MemAvailable:")
    {
      available = kb * 1024;
    }
    meminfo.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  }
  return available == std::numeric_limits<std::size_t>::max() ||
    (available > extra && available - extra >= total / 10);
}
} // namespace

//------------------------------------------------------------------------------
bool vtkWhittedGeometryTimeCache::Key::operator<(const Key& o) const
{
  return std::make_tuple(this->Mapper, this->Options.Tie(), this->State, this->Content) <
    std::make_tuple(o.Mapper, o.Options.Tie(), o.State, o.Content);
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryTimeCache::SetLimit(std::size_t bytes)
{
  this->Limit = bytes;
  this->Trim();
}

//------------------------------------------------------------------------------
bool vtkWhittedGeometryTimeCache::WorthKeeping(
  const Key& key, bool hasTime, double time, bool nextHasTime, double nextTime)
{
  // A time step the time moved on from, or contents shown (and replaced) before
  const bool reShown = this->SeenBefore(key);
  const bool timeStep = hasTime && (!nextHasTime || nextTime != time);
  return reShown || timeStep;
}

//------------------------------------------------------------------------------
bool vtkWhittedGeometryTimeCache::SeenBefore(const Key& key)
{
  auto it = this->Seen.find(key);
  const bool before = it != this->Seen.end();
  this->Seen[key] = ++this->Uses;
  while (this->Seen.size() > SeenLimit)
  {
    auto oldest = this->Seen.begin();
    for (auto s = this->Seen.begin(); s != this->Seen.end(); ++s)
    {
      oldest = s->second < oldest->second ? s : oldest;
    }
    this->Seen.erase(oldest);
  }
  return before;
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryTimeCache::Insert(const Key& key, Entry entry)
{
  if (entry.Bytes > this->Limit || !MemoryAllows(entry.Bytes))
  {
    return; // dropped: its objects are freed
  }
  entry.LastUse = ++this->Uses;
  this->Bytes += entry.Bytes;
  auto it = this->Entries.find(key);
  if (it != this->Entries.end())
  {
    this->Bytes -= it->second.Bytes;
    it->second = std::move(entry);
  }
  else
  {
    this->Entries.emplace(key, std::move(entry));
  }
  this->Trim();
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryTimeCache::Trim()
{
  while (!this->Entries.empty() && (this->Bytes > this->Limit || !MemoryAllows(0)))
  {
    auto oldest = this->Entries.begin();
    for (auto it = this->Entries.begin(); it != this->Entries.end(); ++it)
    {
      oldest = it->second.LastUse < oldest->second.LastUse ? it : oldest;
    }
    this->Bytes -= oldest->second.Bytes;
    this->Entries.erase(oldest);
  }
}

//------------------------------------------------------------------------------
bool vtkWhittedGeometryTimeCache::Take(const Key& key, Entry& entry)
{
  auto it = this->Entries.find(key);
  if (it == this->Entries.end())
  {
    return false;
  }
  entry = std::move(it->second);
  this->Bytes -= entry.Bytes;
  this->Entries.erase(it);
  return true;
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryTimeCache::RemoveOtherMappers(const std::set<vtkMapper*>& used)
{
  for (auto it = this->Entries.begin(); it != this->Entries.end();)
  {
    if (used.count(it->first.Mapper))
    {
      ++it;
      continue;
    }
    this->Bytes -= it->second.Bytes;
    it = this->Entries.erase(it);
  }
  for (auto it = this->Seen.begin(); it != this->Seen.end();)
  {
    it = used.count(it->first.Mapper) ? std::next(it) : this->Seen.erase(it);
  }
}

//------------------------------------------------------------------------------
void vtkWhittedGeometryTimeCache::Clear()
{
  this->Entries.clear();
  this->Seen.clear();
  this->Bytes = 0;
}
