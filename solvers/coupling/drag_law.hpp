#pragma once
// The drag closure a scene chose (coupling.drag), callable on the device: the
// momentum-exchange coefficient K(eps, |u_f - u_s|) of the law, each law in its own
// header.
#include "solvers/coupling/di_felice.hpp"
#include "solvers/coupling/ergun_wen_yu.hpp"

#include <stdexcept>
#include <string>

namespace dvisph {

struct DragLaw {
  enum class Kind : int { ergun_wen_yu, di_felice } kind;
  ErgunWenYu ergun_wen_yu;
  DiFelice di_felice;

  DragLaw(const std::string& name, Real rho, Real nu, Real d, Real eps_switch)
      : kind(name == "di_felice" ? Kind::di_felice : Kind::ergun_wen_yu),
        ergun_wen_yu{rho, rho * nu, d, eps_switch},
        di_felice{rho, rho * nu, d} {
    if (name != "ergun_wen_yu" && name != "di_felice")
      throw std::invalid_argument("unknown drag law " + name);
    if (!(nu > 0)) throw std::invalid_argument("drag: needs a viscous fluid (nu > 0)");
  }

  KOKKOS_INLINE_FUNCTION Real operator()(Real eps, Real slip) const {
    return kind == Kind::di_felice ? di_felice(eps, slip) : ergun_wen_yu(eps, slip);
  }
};

}  // namespace dvisph
