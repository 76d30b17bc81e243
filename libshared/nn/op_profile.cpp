#include "nn/op_profile.h"

#include <algorithm>
#include <string_view>

namespace df::nn {

std::string OpProfile::op_name(const char* where) {
  std::string_view s(where ? where : "?");
  // The name is the identifier just before the parameter list's '(' (skip "operator()" forms).
  const auto paren = s.find('(');
  if (paren != std::string_view::npos) s = s.substr(0, paren);
  if (!s.empty() && s.back() == '>') s = s.substr(0, s.find('<'));  // matmul_repeated<float>
  const auto sep = s.find_last_of(": ");
  if (sep != std::string_view::npos) s = s.substr(sep + 1);
  return s.empty() ? std::string("?") : std::string(s);
}

OpProfile::Row& OpProfile::row(const char* where) {
  auto it = names_.find(where);
  if (it == names_.end()) it = names_.emplace(where, op_name(where)).first;
  return rows_[it->second];
}

void OpProfile::add_forward(const char* where, double seconds, double flops, double bytes) {
  Row& r = row(where);
  ++r.calls;
  r.forward_s += seconds;
  r.forward_flops += flops;
  r.bytes += bytes;
}

void OpProfile::add_backward(const char* where, double seconds, double flops, double bytes) {
  Row& r = row(where);
  r.backward_s += seconds;
  r.backward_flops += flops;
  r.bytes += bytes;
}

std::vector<std::pair<std::string, OpProfile::Row>> OpProfile::rows() const {
  std::vector<std::pair<std::string, Row>> out(rows_.begin(), rows_.end());
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.second.forward_s + a.second.backward_s > b.second.forward_s + b.second.backward_s;
  });
  return out;
}

}  // namespace df::nn
