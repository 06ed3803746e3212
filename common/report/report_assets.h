#pragma once
// The fit report's own style sheet and viewer script, compiled in from
// common/report/assets/ (report.css, viewer.js) so that the stage needs no
// file beside its binary but three.js.
namespace gp::report {

const char* report_css();
const char* viewer_js();

}  // namespace gp::report
