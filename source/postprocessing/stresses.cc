#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <feticontact/postprocessing/stresses.h>

#include <cmath>

namespace FetiContact
{
  using namespace dealii;

  std::vector<SymmetricTensor<2, 3>>
  cell_strains(const Subdomain &subdomain, const Mapping<3> &mapping, const Vector<double> &u)
  {
    const auto                      &fe = subdomain.dof_handler.get_fe();
    FEValues<3>                      fe_values(mapping, fe, QGaussSimplex<3>(1), update_gradients);
    const FEValuesExtractors::Vector displacement(0);
    std::vector<SymmetricTensor<2, 3>> at_point(1);
    std::vector<SymmetricTensor<2, 3>> strain(subdomain.mesh.n_active_cells());
    for (const auto &cell : subdomain.dof_handler.active_cell_iterators())
      {
        fe_values.reinit(cell);
        fe_values[displacement].get_function_symmetric_gradients(u, at_point);
        strain[cell->active_cell_index()] = at_point[0];
      }
    return strain;
  }

  std::vector<SymmetricTensor<2, 3>>
  cell_stresses(const Subdomain &subdomain, const Mapping<3> &mapping, const Vector<double> &u)
  {
    const double lambda = subdomain.body.parameters.material.lambda();
    const double mu     = subdomain.body.parameters.material.mu();
    auto         stress = cell_strains(subdomain, mapping, u);
    for (auto &sigma : stress)
      sigma = lambda * trace(sigma) * unit_symmetric_tensor<3>() + 2 * mu * sigma;
    return stress;
  }

  double
  von_mises(const SymmetricTensor<2, 3> &sigma)
  {
    const auto s = deviator(sigma);
    return std::sqrt(1.5 * (s * s));
  }
} // namespace FetiContact
