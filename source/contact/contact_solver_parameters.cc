#include <feticontact/base/input_parsing.h>
#include <feticontact/contact/contact_solver_parameters.h>

#include <array>
#include <cmath>

namespace FetiContact::Parameters
{
  using namespace dealii;

  void
  ContactSolver::declare_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact solver");
    prm.declare_entry("Friction law",
                      "coulomb",
                      Patterns::Selection("coulomb|tresca"),
                      "For zones with a friction coefficient μ > 0: 'coulomb' (slip bound "
                      "g = μ λ_N, the fixed point found by successive approximations, MSA) or "
                      "'tresca' (the given 'Slip bound').");
    prm.declare_entry("Slip bound",
                      "0",
                      Patterns::Double(0),
                      "Tresca: the slip bound g of every contact node with μ > 0, a nodal force "
                      "(N).");
    prm.declare_entry(
      "Algorithm",
      "mpgp",
      Patterns::Selection("mpgp|algorithm 1|algorithm 2|polygonal"),
      "'mpgp': MSA outer loop, each step one MPGP over bounds × discs inside "
      "SMALBE with the projector. The paper's algorithms (Kučera, Haslinger, Dostál), for reproducing "
      "its tables: 'algorithm 1' (MSA outer loop, SMALBE with block Gauss–Seidel: "
      "MPRGP on λ_N, λ_E, then KPG on the tangential discs); 'algorithm 2' (MSA "
      "and the augmented Lagrangian merged in one loop: one MPRGP and one KPG "
      "solve and one multiplier update per iteration); 'polygonal' (the disc "
      "replaced by a regular 2s-gon with s multipliers in boxes, MPRGP only).");
    prm.declare_entry("Accuracy",
                      "engineering",
                      Patterns::Selection("draft|engineering|reference"),
                      "A preset of the two relative tolerances below: 'draft' MSA 1e-3, QP "
                      "1e-4 (trial runs), 'engineering' MSA 1e-6, QP 1e-8, 'reference' MSA = "
                      "QP = 1e-10 (verification). Either tolerance given as a number overrides "
                      "its preset.");
    prm.declare_entry("QP relative tolerance",
                      "preset",
                      Patterns::Anything(),
                      "A number in (0, 1) or 'preset' (from Accuracy): SMALBE stops when "
                      "‖g^P(λ)‖ ≤ tol ‖h‖ and ‖Gλ − e‖ ≤ tol ‖e‖.");
    prm.declare_entry("MSA relative tolerance",
                      "preset",
                      Patterns::Anything(),
                      "A number in (0, 1) or 'preset' (from Accuracy): successive approximations "
                      "stop when the slip bound changes by less than this fraction, "
                      "‖g_new − g‖ ≤ tol ‖g_new‖.");
    prm.declare_entry("Maximum MSA iterations",
                      "100",
                      Patterns::Integer(1),
                      "The limit of the successive approximations of the slip bound.");
    prm.enter_subsection("Expert");
    declare_expert_parameters(prm);
    prm.leave_subsection();
    prm.enter_subsection("MPGP");
    QP::MPGPParameters::declare_parameters(prm);
    prm.leave_subsection();
    prm.enter_subsection("SMALBE");
    QP::SMALBEParameters::declare_parameters(prm);
    prm.leave_subsection();
    prm.leave_subsection();
  }

  void
  ContactSolver::declare_expert_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Polygon directions",
                      "4",
                      Patterns::Integer(2),
                      "polygonal: s, the number of tangential multipliers per node (2: square, "
                      "4: octagon).");
    prm.declare_entry("Inexact MSA factor",
                      "auto",
                      Patterns::Anything(),
                      "A number c in [0, 1) or 'auto' (0.001 for mpgp, 0.01 otherwise): MSA step "
                      "j solves its Tresca problem only to the relative tolerance max(QP relative "
                      "tolerance, c × the relative change of the slip bound in step j − 1) (1 in "
                      "step 1); MSA stops only after a step solved to the QP relative tolerance. "
                      "0: every step to the QP relative tolerance.");
    prm.declare_entry("Gauss-Seidel sweeps",
                      "1",
                      Patterns::Integer(1),
                      "algorithm 1: block Gauss–Seidel sweeps (λ_c, then λ_t) per inner problem.");
    prm.declare_entry("Relaxation",
                      "1",
                      Patterns::Double(0, 1),
                      "ω ∈ (0, 1] in the slip-bound update g ← (1 − ω) g + ω μ λ_N (1: plain "
                      "MSA); below 1 for large friction coefficients, where MSA may oscillate.");
    prm.declare_entry("Friction continuation steps",
                      "1",
                      Patterns::Integer(1),
                      "n: solve the Coulomb problem for μ/n, 2μ/n, …, μ in turn, each stage "
                      "starting from the solution of the previous one (the intermediate stages "
                      "to 100 × the MSA tolerance). 1: no continuation.");
  }

  void
  ContactSolver::parse_parameters(ParameterHandler &prm)
  {
    prm.enter_subsection("Contact solver");
    friction_law =
      prm.get("Friction law") == "coulomb" ? FrictionLaw::coulomb : FrictionLaw::tresca;
    slip_bound          = prm.get_double("Slip bound");
    const std::string a = prm.get("Algorithm");
    algorithm           = a == "algorithm 1" ? Algorithm::algorithm_1 :
                          a == "algorithm 2" ? Algorithm::algorithm_2 :
                          a == "mpgp"        ? Algorithm::mpgp :
                                               Algorithm::polygonal;
    // The presets of Accuracy: {MSA, QP} relative tolerances.
    const std::string accuracy  = prm.get("Accuracy");
    const auto        preset    = accuracy == "draft"     ? std::array<double, 2>{{1e-3, 1e-4}} :
                                  accuracy == "reference" ? std::array<double, 2>{{1e-10, 1e-10}} :
                                                            std::array<double, 2>{{1e-6, 1e-8}};
    const auto        tolerance = [&](const std::string &entry, const double preset_value) {
      const std::string text = InputParsing::trim(prm.get(entry));
      if (text == "preset")
        return preset_value;
      const double value = InputParsing::parse_double(text, "Contact solver/" + entry);
      require(value > 0 && value < 1,
              "Contact solver/" + entry + " must be 'preset' or a number in (0, 1); got '" + text +
                "'.");
      return value;
    };
    msa_tolerance      = tolerance("MSA relative tolerance", preset[0]);
    qp_tolerance       = tolerance("QP relative tolerance", preset[1]);
    max_msa_iterations = prm.get_integer("Maximum MSA iterations");
    prm.enter_subsection("Expert");
    parse_expert_parameters(prm);
    prm.leave_subsection();
    parse_qp_parameters(prm);
    prm.leave_subsection();
  }

  void
  ContactSolver::parse_expert_parameters(ParameterHandler &prm)
  {
    const std::string path = "Contact solver/Expert/";
    const bool        mpgp = algorithm == Algorithm::mpgp;
    polygon_directions     = prm.get_integer("Polygon directions");
    const std::string text = InputParsing::trim(prm.get("Inexact MSA factor"));
    inexact_msa_factor     = mpgp ? 1e-3 : 1e-2;
    if (text != "auto")
      inexact_msa_factor = InputParsing::parse_double(text, path + "Inexact MSA factor");
    require(inexact_msa_factor >= 0 && inexact_msa_factor < 1,
            path + "Inexact MSA factor must be 'auto' or a number in [0, 1); got '" + text + "'.");
    gauss_seidel_sweeps = prm.get_integer("Gauss-Seidel sweeps");
    relaxation          = prm.get_double("Relaxation");
    require(relaxation > 0, path + "Relaxation must be in (0, 1]; got 0.");
    continuation_steps = prm.get_integer("Friction continuation steps");
  }

  void
  ContactSolver::parse_qp_parameters(ParameterHandler &prm)
  {
    // The 'auto' values: the best measured configuration for mpgp, the published one for the
    // paper's algorithms and the polygonal baseline.
    const bool is_mpgp                = algorithm == Algorithm::mpgp;
    using ArcScale                    = QP::MPGPParameters::ArcScale;
    using Expansion                   = QP::MPGPParameters::Expansion;
    using Bound                       = QP::SMALBEParameters::HessianNormBound;
    using Equality                    = QP::SMALBEParameters::EqualityConstraint;
    mpgp                              = QP::MPGPParameters();
    mpgp.expansion                    = is_mpgp ? Expansion::projected_cg : Expansion::fixed_step;
    mpgp.recursive_gradient_tolerance = is_mpgp ? 0.1 : 0;
    mpgp.arc_scale_estimate           = is_mpgp ? ArcScale::mean_diagonal : ArcScale::norm_bound;
    prm.enter_subsection("MPGP");
    mpgp.parse_parameters(prm);
    prm.leave_subsection();

    smalbe = QP::SMALBEParameters();
    // Algorithm 2 with Coulomb friction repeats its SMALBE solve warm (CombinedLoop).
    smalbe.max_outer_iterations =
      algorithm == Algorithm::algorithm_2 && friction_law == FrictionLaw::coulomb ? 200 : 2000;
    smalbe.hessian_norm_bound = is_mpgp ? Bound::max : Bound::sum;
    smalbe.penalty_factor     = 0;
    prm.enter_subsection("SMALBE");
    smalbe.parse_parameters(prm);
    prm.leave_subsection();
    const bool projector   = smalbe.equality_constraint == Equality::projector;
    penalty_projected_norm = is_mpgp && projector;
    if (!(smalbe.penalty_factor > 0)) // 'auto'
      smalbe.penalty_factor = penalty_projected_norm              ? 5.0 :
                              algorithm == Algorithm::algorithm_1 ? 0.1 :
                              algorithm == Algorithm::algorithm_2 ? 0.03 :
                                                                    1.0;
  }
} // namespace FetiContact::Parameters
