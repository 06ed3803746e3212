#pragma once
// The command line of a motion run's solver and contact (simulate-adapt's flags): each option with
// its default and unit in --help, written to a MotionRunOptions and the named choices below.
#include <string>

#include <CLI/CLI.hpp>

#include "adapt/garment_motion.h"

namespace gp::adapt {

// The options given by name; apply_choices() turns them into MotionRunOptions.
struct MotionChoices {
  std::string equilibrium = "dynamic";  // --solver: static or dynamic (MotionRunOptions::settle.equilibrium)
  std::string linear_solver = "refactor";  // --linear-solver: refactor or pcg (SimulatorOptions::strategy)
  std::string static_contact = "barrier";  // --static-contact: barrier or active_set (StaticSolveOptions::contact)
  std::string contact = "velocity", pinch_gaps = "ray", continuous = "on", hand_hulls = "on";
  CLI::Option* thickness = nullptr;     // --contact-thickness, to tell whether it was given
  bool thickness_given() const { return thickness && thickness->count() > 0; }
};

// Adds --solver, the static solve's options, --reach, --linear-solver, --cg-tolerance, the contact's
// options and --workers (whose default is 2 where the machine has two cores).
void add_solver_and_contact_options(CLI::App& app, MotionRunOptions& options, MotionChoices& choices);
void apply_choices(const MotionChoices& choices, MotionRunOptions& options);

}  // namespace gp::adapt
