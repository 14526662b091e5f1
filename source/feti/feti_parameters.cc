#include <feticontact/base/input_parsing.h>
#include <feticontact/feti/feti_parameters.h>
#include <feticontact/local_solvers/local_solver.h>

namespace FetiContact::Parameters
{
  using namespace dealii;

  void
  Feti::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("FETI");
    prm.declare_entry(
      "Dirichlet treatment",
      "total",
      Patterns::Selection("primal|total"),
      "'total': TFETI, Dirichlet conditions are rows of B_E and every subdomain "
      "floats (robust: the default). 'primal': Dirichlet conditions are "
      "eliminated in the subdomains (the way of Kučera, Haslinger and Dostál: subdomains touching a "
      "clamped face are anchored); subdomains that touch Γ_u in a few vertices "
      "only are then nearly floating and limit the attainable accuracy.");
    prm.declare_entry("Local solver",
                      "cholmod",
                      Patterns::Selection(LocalSolver::available_backends()),
                      "Sparse direct solver for the regularized subdomain stiffness matrices: "
                      "'cholmod' (SuiteSparse supernodal Cholesky, with the project's "
                      "triangular solves), 'cholmod-library-solves' (the same factor with "
                      "CHOLMOD's own solves, about a third slower: the arithmetic of runs made "
                      "before the project's solves), 'amesos2-klu2' (Trilinos "
                      "Amesos2 KLU2), 'amesos-mumps' (Trilinos Amesos MUMPS), 'umfpack' "
                      "(SuiteSparse UMFPACK through deal.II). See doc/local_solvers.md for "
                      "timings.");
    prm.declare_entry(
      "Contact rows at interfaces",
      "lowest copy",
      Patterns::Selection("lowest copy|average"),
      "How a contact row (N, T1, T2) takes a contact node that lies on a "
      "subdomain interface and so has p ≥ 2 glued copies. 'lowest copy' (the "
      "default): the row acts on the copy in the lowest-numbered subdomain. "
      "'average': the row acts on the mean of the p copies, scaled by √p (by "
      "√((1 + 1)/(1/p + 1/q)) between two bodies with p and q copies) so that it "
      "keeps its length; it is then orthogonal to the gluing rows, so that on a "
      "rigid obstacle B has orthonormal rows. The node's multipliers are then the contact force "
      "divided by that scale; all output is the force itself. The solution is "
      "the same. On the brick with H/h = 8 (doc/performance.md) 'average' took "
      "9–13 % fewer applications of F up to 135,000 unknowns and 12 % more at "
      "313,632 and at 1,037,232.");
    prm.declare_entry(
      "Coarse factor",
      "per node",
      Patterns::Selection("per node|per rank"),
      "Where the factor of the coarse matrix GGᵀ is kept. 'per node' (the default): the first "
      "MPI rank of every node assembles and factorizes GGᵀ, and the node's ranks solve with the "
      "one factor in shared memory (POSIX shared memory, /dev/shm); 'per rank': every rank "
      "assembles, factorizes and keeps its own. The results are the same to the last digit; "
      "'per node' stores the factor once per node and factorizes it once per node "
      "(doc/performance.md, \"The coarse problem past this machine\"). On one rank per node "
      "the two are the same.");
    QP::ProjectedCGParameters::declare_parameters(prm);
    prm.declare_entry("Preconditioner",
                      "lumped",
                      Patterns::Selection("none|lumped"),
                      "Preconditioner of the projected CG of problems without contact: 'lumped' "
                      "(the default): the lumped FETI preconditioner P D B K Bᵀ D P with "
                      "D = diag(B Bᵀ)⁻¹, one sparse multiplication by every K_i per iteration, "
                      "no solve; about 3 times fewer iterations, nearly independent of the "
                      "number of subdomains. 'none': plain projected CG. The contact "
                      "solvers do not use it.");
    prm.leave_subsection();
  }

  void
  Feti::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("FETI");
    dirichlet_treatment  = prm.get("Dirichlet treatment") == "primal" ? DirichletTreatment::primal :
                                                                        DirichletTreatment::total;
    local_solver         = prm.get("Local solver");
    average_contact_rows = prm.get("Contact rows at interfaces") == "average";
    coarse_factor =
      prm.get("Coarse factor") == "per rank" ? CoarseFactor::per_rank : CoarseFactor::per_node;
    projected_cg.parse_parameters(prm);
    lumped_preconditioner = prm.get("Preconditioner") == "lumped";
    prm.leave_subsection();
  }
} // namespace FetiContact::Parameters
