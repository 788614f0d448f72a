#pragma once
// Particles of a scene (host side, once at start): fluid boxes on a lattice of the
// scene spacing, tank walls as `wall_layers` layers outside the inner faces, and the
// gate as layers on the downstream side of its plane. Every particle has the volume
// dx^D, so the Laplacian pair weights are symmetric.
#include "src/core/lattice.hpp"
#include "src/scene.hpp"

#include <vector>

namespace dvisph {

template <int D>
struct SceneParticles {
  std::vector<Vec<D>> x;
  std::vector<Kind> kind;
  Vec<D> domain_lo, domain_hi;  // particles must stay inside (or wrap, along periodic axes)
};

template <int D>
Vec<D> to_vec(const std::vector<double>& v) {
  Vec<D> r;
  for (int k = 0; k < D; ++k) r[k] = v[k];
  return r;
}

template <int D>
SceneParticles<D> scene_particles(const Scene& s) {
  SceneParticles<D> out;
  const Real dx = s.spacing;
  const Vec<D> lo = to_vec<D>(s.tank.lo), hi = to_vec<D>(s.tank.hi);
  auto add = [&](const std::vector<Vec<D>>& pts, Kind k) {
    out.x.insert(out.x.end(), pts.begin(), pts.end());
    out.kind.insert(out.kind.end(), pts.size(), k);
  };
  for (const auto& b : s.fluid)
    add(lattice<D>(to_vec<D>(b.lo), to_vec<D>(b.hi), dx, s.jitter * dx), Kind::fluid);

  // walls: the shell between the inner box and the box grown by the layers, on the
  // lattice continued from the inner faces (open top: no shell above hi; a periodic axis
  // has none on either side)
  const Real thick = s.wall_layers * dx;
  Vec<D> wlo = lo, whi = hi;
  for (int k = 0; k < D; ++k)
    if (!s.wraps(k)) wlo[k] -= thick, whi[k] += thick;
  if (s.open_top && !s.wraps(D - 1)) whi[D - 1] = hi[D - 1];
  for (const auto& p : lattice<D>(wlo, whi, dx)) {
    bool inside = true;
    for (int k = 0; k < D; ++k) inside = inside && (s.wraps(k) || (p[k] > lo[k] && p[k] < hi[k]));
    if (!inside) {
      out.x.push_back(p);
      out.kind.push_back(Kind::wall);
    }
  }
  if (s.gate) {
    Vec<D> glo = lo, ghi = hi;
    glo[0] = s.gate->x;
    ghi[0] = s.gate->x + thick;
    add(lattice<D>(glo, ghi, dx), Kind::gate);
  }
  // room above an open top for splashes; beyond the domain a particle is lost (along a
  // periodic axis the domain is the tank, and a particle leaving it wraps)
  const Real margin = thick + 4 * dx;
  out.domain_lo = wlo;
  out.domain_hi = whi;
  for (int k = 0; k < D; ++k)
    if (!s.wraps(k)) out.domain_lo[k] -= margin, out.domain_hi[k] += margin;
  if (s.open_top && !s.wraps(D - 1)) out.domain_hi[D - 1] += hi[D - 1] - lo[D - 1];
  return out;
}

}  // namespace dvisph
