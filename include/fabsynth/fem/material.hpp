// SPDX-License-Identifier: MIT
#pragma once
/// @file material.hpp  Isotropic linear elastic material (E, nu, density) with printing presets.
///
/// Units: E in MPa (N/mm^2), density in t/mm^3 (consistent mm-N-s units: 1 g/cm^3 = 1e-9 t/mm^3),
/// so density * acceleration [mm/s^2] is a force per volume in N/mm^3.
///
/// Usage:
///   auto pla = fabsynth::fem::isotropic_material::pla();
///   Eigen::Matrix<double, 6, 6> C = pla.elasticity();   // sigma = C * eps (Voigt, engineering shear)
#include <Eigen/Core>

#include <cmath>
#include <string>

#include "fabsynth/core/error.hpp"

namespace fabsynth::fem {

/// Voigt order used everywhere in fem/: (xx, yy, zz, yz, xz, xy). Strain vectors hold ENGINEERING
/// shear strains (gamma_yz = 2 eps_yz, ...), so sigma = C * eps with C(3,3) = C(4,4) = C(5,5) = mu.
using voigt6 = Eigen::Matrix<double, 6, 1>;

struct isotropic_material {
    double E = 0;        ///< Young's modulus [MPa]
    double nu = 0;       ///< Poisson's ratio [-], in (-1, 0.5)
    double density = 0;  ///< mass density [t/mm^3] (1 g/cm^3 = 1e-9 t/mm^3)

    /// Throws invalid_input unless E > 0, -1 < nu < 0.5, density >= 0 (all finite).
    void validate() const {
        if (!(std::isfinite(E) && E > 0))
            throw invalid_input("isotropic_material: Young's modulus E must be finite and > 0, got " + std::to_string(E));
        if (!(std::isfinite(nu) && nu > -1.0 && nu < 0.5))
            throw invalid_input("isotropic_material: Poisson's ratio nu must lie in (-1, 0.5), got " + std::to_string(nu));
        if (!(std::isfinite(density) && density >= 0))
            throw invalid_input("isotropic_material: density must be finite and >= 0, got " + std::to_string(density));
    }
    /// First Lame parameter lambda = E nu / ((1 + nu)(1 - 2 nu)) [MPa].
    [[nodiscard]] double lame_lambda() const { return E * nu / ((1 + nu) * (1 - 2 * nu)); }
    /// Shear modulus mu = G = E / (2 (1 + nu)) [MPa].
    [[nodiscard]] double shear_modulus() const { return E / (2 * (1 + nu)); }
    /// Bulk modulus K = E / (3 (1 - 2 nu)) [MPa].
    [[nodiscard]] double bulk_modulus() const { return E / (3 * (1 - 2 * nu)); }

    /// 6x6 elasticity matrix in Voigt order (xx, yy, zz, yz, xz, xy), engineering shear strains.
    [[nodiscard]] Eigen::Matrix<double, 6, 6> elasticity() const {
        const double l = lame_lambda(), mu = shear_modulus();
        Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) C(i, j) = l;
            C(i, i) = l + 2 * mu;
            C(3 + i, 3 + i) = mu;
        }
        return C;
    }
    /// 3x3 plane-stress elasticity in (xx, yy, xy) with engineering shear [MPa].
    [[nodiscard]] Eigen::Matrix3d plane_stress() const {
        const double f = E / (1 - nu * nu);
        Eigen::Matrix3d D;
        D << f, f * nu, 0, f * nu, f, 0, 0, 0, f * (1 - nu) / 2;
        return D;
    }

    /// PLA: E = 3500 MPa, nu = 0.36, 1.24 g/cm^3. E and density are in the range of NatureWorks'
    /// Ingeo 4043D data sheet (tensile modulus 3.6 GPa, specific gravity 1.24); nu = 0.36 is the
    /// value commonly used for PLA in the FE literature (e.g. Farah, Anderson & Langer, "Physical
    /// and mechanical properties of PLA...", Adv. Drug Deliv. Rev. 107, 2016, table 2: nu 0.36).
    /// Values recalled from these sources, not re-measured; printed parts are anisotropic and
    /// typically 10-30% softer.
    static isotropic_material pla() { return {3500.0, 0.36, 1.24e-9}; }
    /// ABS: E = 2200 MPa, nu = 0.35, 1.04 g/cm^3 (Stratasys ABSplus-P430 data sheet: tensile
    /// modulus 2200 MPa (XZ), specific gravity 1.04; nu = 0.35 is the usual handbook value for ABS).
    /// Values recalled from these sources, not re-measured.
    static isotropic_material abs() { return {2200.0, 0.35, 1.04e-9}; }
    /// PETG (lamp shades, outdoor parts): E = 2100 MPa, nu = 0.38, 1.27 g/cm^3. E and density as on
    /// typical PETG filament data sheets (tensile modulus 2.0-2.2 GPa, 1.27 g/cm^3); filament sheets
    /// rarely state nu, 0.38 is the handbook value of PET. Recalled, not re-measured.
    static isotropic_material petg() { return {2100.0, 0.38, 1.27e-9}; }
    /// PA12 laser-sintered (nylon jewellery and lamp parts): E = 1650 MPa, nu = 0.39, 0.93 g/cm^3:
    /// EOS PA 2200 data sheet (tensile modulus 1650 MPa, density of laser-sintered parts 0.93
    /// g/cm^3); nu = 0.39 is the handbook value of polyamide 12. Recalled, not re-measured.
    static isotropic_material pa12() { return {1650.0, 0.39, 0.93e-9}; }
    /// Stainless steel 316L (laser-melted or binder-jet jewellery): E = 193 GPa, nu = 0.30,
    /// 8.0 g/cm^3: the handbook values of wrought 316L (ASM; nu 0.27-0.30). Recalled, not re-measured.
    static isotropic_material steel_316l() { return {193000.0, 0.30, 8.0e-9}; }
    /// Titanium Ti-6Al-4V (laser-melted jewellery): E = 113.8 GPa, nu = 0.342, 4.43 g/cm^3: ASM's
    /// values for annealed Ti-6Al-4V. Recalled, not re-measured.
    static isotropic_material ti64() { return {113800.0, 0.342, 4.43e-9}; }

    friend bool operator==(const isotropic_material&, const isotropic_material&) = default;
};

}  // namespace fabsynth::fem
