#include "reference/validation.h"

namespace nurbs {

void validate_trim(const Surface&, int, std::string_view) {}

}  // namespace nurbs
