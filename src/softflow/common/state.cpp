#include "softflow/common/state.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "softflow/common/error.hpp"

namespace softflow {

void StateRecord::set(const std::string& key, int value) {
  entries_[key] = {Kind::integer, {static_cast<double>(value)}, 1};
}

void StateRecord::set(const std::string& key, double value) {
  entries_[key] = {Kind::real, {value}, 1};
}

void StateRecord::set(const std::string& key, std::vector<double> values, int columns) {
  entries_[key] = {Kind::array, std::move(values), columns};
}

void StateRecord::set(const std::string& key, const std::vector<Eigen::Vector3d>& points) {
  std::vector<double> flat;
  flat.reserve(3 * points.size());
  for (const auto& p : points) flat.insert(flat.end(), {p.x(), p.y(), p.z()});
  set(key, std::move(flat), 3);
}

const StateRecord::Entry& StateRecord::find(const std::string& key, Kind kind) const {
  const auto it = entries_.find(key);
  if (it == entries_.end())
    throw InputError(fmt::format("the saved state has no entry '{}' (written by another "
                                 "softflow, or for another case?)", key));
  if (it->second.kind != kind)
    throw InputError(fmt::format("the saved state's entry '{}' has the wrong kind", key));
  return it->second;
}

int StateRecord::get_int(const std::string& key) const {
  const double v = find(key, Kind::integer).values.at(0);
  if (v != std::floor(v) || std::abs(v) > 2147483647.0)
    throw InputError(fmt::format("the saved state's entry '{}' = {} is not an integer", key, v));
  return static_cast<int>(v);
}

double StateRecord::get_double(const std::string& key) const {
  return find(key, Kind::real).values.at(0);
}

const std::vector<double>& StateRecord::get_array(const std::string& key, int columns) const {
  const Entry& e = find(key, Kind::array);
  if (e.columns != columns || e.values.size() % columns != 0)
    throw InputError(fmt::format("the saved state's entry '{}' has {} columns, expected {}", key,
                                 e.columns, columns));
  return e.values;
}

std::vector<Eigen::Vector3d> StateRecord::get_points(const std::string& key) const {
  const auto& flat = get_array(key, 3);
  std::vector<Eigen::Vector3d> points(flat.size() / 3);
  for (std::size_t i = 0; i < points.size(); ++i)
    points[i] = Eigen::Vector3d(flat[3 * i], flat[3 * i + 1], flat[3 * i + 2]);
  return points;
}

void StateRegistry::add(StatePart part) {
  for (const auto& p : parts_)
    if (p.name == part.name)
      throw Error(fmt::format("StateRegistry: a part named '{}' is registered already", part.name));
  parts_.push_back(std::move(part));
}

void StateRegistry::save(StateRecord& record) const { save(record, {}); }

void StateRegistry::restore(const StateRecord& record) const { restore(record, {}); }

namespace {
bool skipped(const StatePart& p, const std::vector<std::string>& skip) {
  return std::find(skip.begin(), skip.end(), p.name) != skip.end();
}
}  // namespace

void StateRegistry::save(StateRecord& record, const std::vector<std::string>& skip) const {
  for (const auto& p : parts_)
    if (!skipped(p, skip)) p.save(record, p.name + "/");
}

void StateRegistry::restore(const StateRecord& record, const std::vector<std::string>& skip) const {
  for (const auto& p : parts_)
    if (!skipped(p, skip)) p.restore(record, p.name + "/");
}

std::vector<std::string> StateRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& p : parts_) out.push_back(p.name);
  return out;
}

}  // namespace softflow
