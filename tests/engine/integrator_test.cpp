// The one mapping between the integrators and their names (scene key integrator.type, summary.json).
#include "engine/steppers/integrator.h"

#include <gtest/gtest.h>

namespace csim {
namespace {

TEST(IntegratorNames, EachNameReadsBackAsItsIntegrator) {
  EXPECT_EQ(integrator_name(Integrator::moreau_jean), "moreau-jean");
  EXPECT_EQ(integrator_name(Integrator::quasi_static), "quasi-static");
  EXPECT_EQ(integrator_name(Integrator::ida), "ida");
  EXPECT_EQ(integrator_name(Integrator::ida_events), "ida-events");
  EXPECT_EQ(integrator_name(Integrator::generalized_alpha), "generalized-alpha");
  for (Integrator integrator : kIntegrators) EXPECT_EQ(integrator_from_name(integrator_name(integrator)), integrator);
}

TEST(IntegratorNames, UnknownNamesAreNothing) {
  EXPECT_FALSE(integrator_from_name("moreau_jean").has_value());  // the enum's spelling is not a name
  EXPECT_FALSE(integrator_from_name("IDA").has_value());
  EXPECT_FALSE(integrator_from_name("").has_value());
}

TEST(IntegratorNames, ListForMessagesAndIdaFamily) {
  EXPECT_EQ(integrator_names(), "moreau-jean, quasi-static, ida, ida-events, generalized-alpha");
  EXPECT_TRUE(is_ida(Integrator::ida));
  EXPECT_TRUE(is_ida(Integrator::ida_events));
  EXPECT_FALSE(is_ida(Integrator::moreau_jean));
  EXPECT_FALSE(is_ida(Integrator::quasi_static));
  EXPECT_FALSE(is_ida(Integrator::generalized_alpha));
  EXPECT_TRUE(is_time_stepping(Integrator::moreau_jean));
  EXPECT_TRUE(is_time_stepping(Integrator::generalized_alpha));
  EXPECT_FALSE(is_time_stepping(Integrator::ida));
  EXPECT_FALSE(is_time_stepping(Integrator::quasi_static));
}

}  // namespace
}  // namespace csim
