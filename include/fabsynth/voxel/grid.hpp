// SPDX-License-Identifier: MIT
#pragma once
/// @file grid.hpp  Regular voxel grids, generic over value type and storage (dense / sparse hash).
///
/// A grid has dims (nx, ny, nz) voxels; voxel (i, j, k) occupies the box
/// [origin + spacing * (i, j, k), origin + spacing * (i + 1, j + 1, k + 1)] in world space (mm).
/// Linear indices are x-fastest: index = i + nx * (j + ny * k).
///
/// Usage:
///   fabsynth::voxel_grid<float> g({64, 64, 64}, {0, 0, 0}, 0.5);      // dense, 0.5 mm voxels
///   g.set({1, 2, 3}, 1.0f);
///   fabsynth::sparse_voxel_grid<fabsynth::vec3> shell(dims, origin, 0.5);  // hash map, thin shells
///   shell.for_each([](ivec3 p, const vec3& n) { ... });                    // stored voxels only
///
/// Size limits (checked before anything is allocated, invalid_input otherwise): every dimension in
/// [1, 2^21]; dense grids at most 2^34 bytes of values (16 GiB); sparse grids at most 2^36 voxels of
/// index space. A 10^12-voxel request is therefore refused by both.
#include <algorithm>
#include <concepts>
#include <cstdint>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <utility>
#include <vector>

#include "fabsynth/core/box.hpp"
#include "fabsynth/core/error.hpp"
#include "fabsynth/core/types.hpp"

namespace fabsynth {

/// Storage policy for voxel values addressed by a linear 64-bit index.
/// Must provide: construction from (voxel count, background value); get(i) (O(1)); set(i, v)
/// (O(1), amortised for hash storage); for_each_stored(f) calling f(index, value) in increasing
/// index order; stored() = number of stored entries; background(); is_sparse.
template <class S>
concept voxel_storage = requires(S s, const S cs, std::uint64_t i, const typename S::value_type& v) {
    typename S::value_type;
    { S(std::uint64_t{1}, v) };
    { cs.get(i) } -> std::convertible_to<typename S::value_type>;
    s.set(i, v);
    { cs.stored() } -> std::convertible_to<std::uint64_t>;
    { cs.background() } -> std::convertible_to<typename S::value_type>;
    { S::is_sparse } -> std::convertible_to<bool>;
};

/// Contiguous storage: one value per voxel. bool is stored as std::uint8_t so that distinct voxels
/// are distinct memory locations (safe to write from parallel loops).
template <class T>
class dense_storage {
public:
    using value_type = T;
    using element_type = std::conditional_t<std::is_same_v<T, bool>, std::uint8_t, T>;
    static constexpr bool is_sparse = false;
    /// Largest total size of values accepted (bytes).
    static constexpr std::uint64_t max_bytes = std::uint64_t{1} << 34;

    dense_storage(std::uint64_t count, const T& background) : background_(background) {
        if (count > max_bytes / sizeof(element_type))
            throw invalid_input("dense voxel grid of " + std::to_string(count) + " voxels needs more than " +
                                std::to_string(max_bytes >> 30) + " GiB; use a coarser grid or sparse storage");
        data_.assign(static_cast<std::size_t>(count), static_cast<element_type>(background));
    }
    [[nodiscard]] T get(std::uint64_t i) const { return static_cast<T>(data_[static_cast<std::size_t>(i)]); }
    void set(std::uint64_t i, const T& v) { data_[static_cast<std::size_t>(i)] = static_cast<element_type>(v); }
    /// Direct reference (dense only).
    [[nodiscard]] element_type& ref(std::uint64_t i) { return data_[static_cast<std::size_t>(i)]; }
    [[nodiscard]] std::uint64_t stored() const noexcept { return data_.size(); }
    [[nodiscard]] const T& background() const noexcept { return background_; }
    /// Visits every voxel (a dense grid stores them all).
    template <class F>
    void for_each_stored(F&& f) const {
        for (std::size_t i = 0; i < data_.size(); ++i) f(static_cast<std::uint64_t>(i), static_cast<T>(data_[i]));
    }
    [[nodiscard]] const std::vector<element_type>& data() const noexcept { return data_; }
    [[nodiscard]] std::vector<element_type>& data() noexcept { return data_; }

private:
    std::vector<element_type> data_;
    T background_;
};

/// Hash-map storage keyed by the linear voxel index; absent voxels read as the background value.
/// Suits thin shells (O(surface) memory). Not safe for concurrent set().
template <class T>
class sparse_storage {
public:
    using value_type = T;
    static constexpr bool is_sparse = true;
    /// Largest index space accepted (voxels): 4096^3.
    static constexpr std::uint64_t max_voxels = std::uint64_t{1} << 36;

    sparse_storage(std::uint64_t count, const T& background) : background_(background) {
        if (count > max_voxels)
            throw invalid_input("sparse voxel grid of " + std::to_string(count) + " voxels exceeds the limit of 2^36 voxels");
    }
    [[nodiscard]] T get(std::uint64_t i) const {
        auto it = map_.find(i);
        return it == map_.end() ? background_ : it->second;
    }
    void set(std::uint64_t i, const T& v) { map_.insert_or_assign(i, v); }
    /// Removes a stored voxel (it reads as background again).
    void erase(std::uint64_t i) { map_.erase(i); }
    [[nodiscard]] bool is_stored(std::uint64_t i) const { return map_.count(i) != 0; }
    [[nodiscard]] std::uint64_t stored() const noexcept { return map_.size(); }
    [[nodiscard]] const T& background() const noexcept { return background_; }
    void reserve(std::size_t n) { map_.reserve(n); }
    /// Visits stored voxels in increasing index order (sorted, so the order is deterministic).
    template <class F>
    void for_each_stored(F&& f) const {
        for (std::uint64_t k : sorted_keys()) f(k, map_.at(k));
    }
    /// Stored indices in increasing order.
    [[nodiscard]] std::vector<std::uint64_t> sorted_keys() const {
        std::vector<std::uint64_t> keys;
        keys.reserve(map_.size());
        for (const auto& kv : map_) keys.push_back(kv.first);
        std::sort(keys.begin(), keys.end());
        return keys;
    }

private:
    std::unordered_map<std::uint64_t, T> map_;
    T background_;
};

/// Placement of a regular grid in space: dims voxels of size spacing (mm) from origin (mm).
struct grid_geometry {
    ivec3 dims{0};
    vec3 origin{0.0};
    vec3 spacing{1.0};

    static constexpr int max_dim = 1 << 21;

    /// Number of voxels (64-bit; dims must be valid).
    [[nodiscard]] std::uint64_t count() const noexcept {
        return static_cast<std::uint64_t>(dims.x) * static_cast<std::uint64_t>(dims.y) * static_cast<std::uint64_t>(dims.z);
    }
    /// Throws invalid_input unless every dim is in [1, 2^21] and origin/spacing are finite
    /// (spacing > 0). `what` names the grid in the message.
    void validate(const char* what = "voxel grid") const {
        for (int a = 0; a < 3; ++a)
            if (dims[a] < 1 || dims[a] > max_dim)
                throw invalid_input(std::string(what) + ": dimension " + std::to_string(a) + " is " +
                                    std::to_string(dims[a]) + ", must be in [1, 2^21]");
        if (!all_finite(origin)) throw invalid_input(std::string(what) + ": origin is not finite");
        if (!all_finite(origin + spacing * vec3(dims))) throw invalid_input(std::string(what) + ": extent overflows");
        for (int a = 0; a < 3; ++a)
            if (!(std::isfinite(spacing[a]) && spacing[a] > 0.0))
                throw invalid_input(std::string(what) + ": spacing must be finite and > 0");
    }
    [[nodiscard]] bool contains(const ivec3& p) const noexcept {
        return p.x >= 0 && p.y >= 0 && p.z >= 0 && p.x < dims.x && p.y < dims.y && p.z < dims.z;
    }
    /// Linear x-fastest index of an in-bounds voxel.
    [[nodiscard]] std::uint64_t index(const ivec3& p) const noexcept {
        return static_cast<std::uint64_t>(p.x) +
               static_cast<std::uint64_t>(dims.x) *
                   (static_cast<std::uint64_t>(p.y) + static_cast<std::uint64_t>(dims.y) * static_cast<std::uint64_t>(p.z));
    }
    /// Inverse of index().
    [[nodiscard]] ivec3 coord(std::uint64_t i) const noexcept {
        const auto nx = static_cast<std::uint64_t>(dims.x), ny = static_cast<std::uint64_t>(dims.y);
        return {static_cast<int>(i % nx), static_cast<int>((i / nx) % ny), static_cast<int>(i / (nx * ny))};
    }
    /// World position (mm) of the voxel centre.
    [[nodiscard]] vec3 center(const ivec3& p) const noexcept { return origin + spacing * (vec3(p) + 0.5); }
    /// World box (mm) of the voxel.
    [[nodiscard]] box3 voxel_box(const ivec3& p) const noexcept {
        return {origin + spacing * vec3(p), origin + spacing * (vec3(p) + 1.0)};
    }
    /// World box (mm) of the whole grid.
    [[nodiscard]] box3 bounds() const noexcept { return {origin, origin + spacing * vec3(dims)}; }
    /// Voxel containing a world point (may be out of bounds; coordinates clamped to +-2^30 so the
    /// conversion never overflows).
    [[nodiscard]] ivec3 voxel_of(const vec3& x) const noexcept {
        ivec3 r;
        for (int a = 0; a < 3; ++a) {
            double c = std::floor((x[a] - origin[a]) / spacing[a]);
            if (std::isnan(c)) c = -1073741824.0;  // NaN input: some voxel outside the grid
            r[a] = static_cast<int>(std::clamp(c, -1073741824.0, 1073741824.0));
        }
        return r;
    }
    friend bool operator==(const grid_geometry&, const grid_geometry&) = default;
};

/// A grid of cubic voxels of size `voxel_size` covering `bounds` with `padding` empty voxels on
/// every side, the longest side spanning `resolution` voxels. Throws invalid_input for an empty or
/// non-finite box or resolution < 1.
[[nodiscard]] inline grid_geometry fit_grid(const box3& bounds, int resolution, int padding = 1) {
    if (bounds.empty() || !all_finite(bounds.lo) || !all_finite(bounds.hi))
        throw invalid_input("fit_grid: bounding box is empty or not finite");
    if (resolution < 1 || resolution > grid_geometry::max_dim / 2)
        throw invalid_input("fit_grid: resolution " + std::to_string(resolution) + " must be in [1, 2^20]");
    if (padding < 0 || padding > 1024) throw invalid_input("fit_grid: padding " + std::to_string(padding) + " must be in [0, 1024]");
    const vec3 ext = bounds.size();
    double h = std::max({ext.x, ext.y, ext.z}) / resolution;
    if (!(h > 0.0)) h = 1.0;  // a single point: any voxel size works
    grid_geometry g;
    g.spacing = vec3(h);
    for (int a = 0; a < 3; ++a) {
        const int n = std::max(1, static_cast<int>(std::ceil(ext[a] / h - 1e-9)));
        g.dims[a] = n + 2 * padding;
        // centre the mesh in the (slightly larger) grid
        g.origin[a] = bounds.center()[a] - 0.5 * h * g.dims[a];
    }
    return g;
}

/// A voxel grid of values T in storage S (default dense). Out-of-bounds reads via at() throw;
/// get()/set() expect in-bounds voxels (checked by FABSYNTH_ASSERT in debug builds).
template <class T, voxel_storage S = dense_storage<T>>
    requires std::same_as<typename S::value_type, T>
class voxel_grid {
public:
    using value_type = T;
    using storage_type = S;

    voxel_grid() : geom_{{1, 1, 1}, vec3(0.0), vec3(1.0)}, store_(1, T{}) {}
    /// Grid of dims voxels from origin (mm) with per-axis voxel spacing (mm); all voxels read as
    /// `background`. Throws invalid_input for invalid dims/spacing or too large a grid.
    explicit voxel_grid(const grid_geometry& g, const T& background = T{}) : geom_(checked(g)), store_(geom_.count(), background) {}
    voxel_grid(ivec3 dims, vec3 origin, vec3 spacing, const T& background = T{})
        : voxel_grid(grid_geometry{dims, origin, spacing}, background) {}
    /// Cubic voxels of edge `voxel_size` (mm).
    voxel_grid(ivec3 dims, vec3 origin, double voxel_size, const T& background = T{})
        : voxel_grid(grid_geometry{dims, origin, vec3(voxel_size)}, background) {}

    [[nodiscard]] const grid_geometry& geometry() const noexcept { return geom_; }
    [[nodiscard]] ivec3 dims() const noexcept { return geom_.dims; }
    [[nodiscard]] vec3 origin() const noexcept { return geom_.origin; }
    [[nodiscard]] vec3 spacing() const noexcept { return geom_.spacing; }
    [[nodiscard]] std::uint64_t size() const noexcept { return geom_.count(); }
    [[nodiscard]] bool contains(const ivec3& p) const noexcept { return geom_.contains(p); }
    [[nodiscard]] std::uint64_t index(const ivec3& p) const noexcept { return geom_.index(p); }
    [[nodiscard]] ivec3 coord(std::uint64_t i) const noexcept { return geom_.coord(i); }
    [[nodiscard]] vec3 center(const ivec3& p) const noexcept { return geom_.center(p); }
    [[nodiscard]] box3 voxel_box(const ivec3& p) const noexcept { return geom_.voxel_box(p); }
    [[nodiscard]] ivec3 voxel_of(const vec3& x) const noexcept { return geom_.voxel_of(x); }
    [[nodiscard]] const S& storage() const noexcept { return store_; }
    [[nodiscard]] S& storage() noexcept { return store_; }
    [[nodiscard]] const T& background() const noexcept { return store_.background(); }

    /// Value of an in-bounds voxel.
    [[nodiscard]] T get(const ivec3& p) const {
        FABSYNTH_ASSERT(contains(p));
        return store_.get(index(p));
    }
    /// Value of a voxel, or background() outside the grid.
    [[nodiscard]] T get_or_background(const ivec3& p) const { return contains(p) ? store_.get(index(p)) : background(); }
    /// Bounds-checked read: throws invalid_input for a voxel outside the grid.
    [[nodiscard]] T at(const ivec3& p) const {
        if (!contains(p))
            throw invalid_input("voxel (" + std::to_string(p.x) + ", " + std::to_string(p.y) + ", " + std::to_string(p.z) +
                                ") is outside the grid");
        return store_.get(index(p));
    }
    /// Writes an in-bounds voxel.
    void set(const ivec3& p, const T& v) {
        FABSYNTH_ASSERT(contains(p));
        store_.set(index(p), v);
    }
    /// Direct reference to a voxel value (dense storage only).
    [[nodiscard]] decltype(auto) operator[](const ivec3& p)
        requires(!S::is_sparse)
    {
        FABSYNTH_ASSERT(contains(p));
        return store_.ref(index(p));
    }
    /// Calls f(ivec3 voxel, T value) for every stored voxel in increasing index order (every voxel
    /// for dense storage; only explicitly set voxels for sparse storage).
    template <class F>
    void for_each(F&& f) const {
        store_.for_each_stored([&](std::uint64_t i, const T& v) { f(coord(i), v); });
    }
    /// Number of stored voxels v with pred(v) (dense: all voxels are stored).
    template <class Pred>
    [[nodiscard]] std::uint64_t count_if(Pred&& pred) const {
        std::uint64_t n = 0;
        store_.for_each_stored([&](std::uint64_t, const T& v) { n += pred(v) ? 1 : 0; });
        return n;
    }

private:
    static const grid_geometry& checked(const grid_geometry& g) {
        g.validate();
        return g;
    }
    grid_geometry geom_;
    S store_;
};

/// A voxel grid on hash storage.
template <class T>
using sparse_voxel_grid = voxel_grid<T, sparse_storage<T>>;

static_assert(voxel_storage<dense_storage<float>>);
static_assert(voxel_storage<sparse_storage<float>>);

}  // namespace fabsynth
