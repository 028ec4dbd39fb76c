// The pass's settings against the settings table (plugin/vtkWhittedSettings.h): every Pass row's
// default, and its clamps at both ends of the range (setting a value outside the range gives the
// nearest end, GetXMinValue / GetXMaxValue are the range). The XML, the view's sources, the
// Python-wrapped pass and the README are checked against the same table by
// testing/settings/check_settings.py, the ParaView view itself by testing/paraview/test_settings.py.

#include "vtkNew.h"
#include "vtkWhittedPass.h"
#include "vtkWhittedSettings.h"

#include <cstdio>
#include <string>

namespace
{
int Failures = 0;

template <typename T>
void Expect(bool ok, const vtkWhittedSetting<T>& row, const char* what, T got, T expected)
{
  if (!ok)
  {
    std::printf("%s: %s is %g, the table says %g\n", row.Name, what, static_cast<double>(got),
      static_cast<double>(expected));
    ++Failures;
  }
}

// Every row: a documentation and a default within its range
template <typename T>
void CheckRow(const vtkWhittedSetting<T>& row)
{
  if (std::string(row.Documentation).size() < 20)
  {
    std::printf("%s: no documentation\n", row.Name);
    ++Failures;
  }
  Expect(row.Minimum <= row.Default && row.Default <= row.Maximum, row, "the default", row.Default,
    row.Minimum);
}

// A numeric setting of the pass: default, clamps below and above, reported range
template <typename T, typename Set, typename Get>
void CheckNumber(const vtkWhittedSetting<T>& row, T minValue, T maxValue, Set set, Get get)
{
  Expect(get() == row.Default, row, "the default", get(), row.Default);
  Expect(minValue == row.Minimum, row, "the minimum", minValue, row.Minimum);
  Expect(maxValue == row.Maximum, row, "the maximum", maxValue, row.Maximum);
  set(row.Minimum - 1);
  Expect(get() == row.Minimum, row, "below the range", get(), row.Minimum);
  set(row.Maximum + 1);
  Expect(get() == row.Maximum, row, "above the range", get(), row.Maximum);
  set(row.Default);
}

// A boolean setting of the pass: default, and both values settable
template <typename Set, typename Get>
void CheckBool(const vtkWhittedSetting<bool>& row, Set set, Get get)
{
  Expect(get() == row.Default, row, "the default", get(), row.Default);
  set(!row.Default);
  Expect(get() == !row.Default, row, "after setting", get(), !row.Default);
  set(row.Default);
}
}

int TestWhittedSettings(int, char*[])
{
  vtkNew<vtkWhittedPass> pass;
  int passRows = 0;

#define WHITTED_CHECK_ROW(owner, type, name, def, min, max, doc)                                   \
  CheckRow(vtkWhittedSettings::name);                                                              \
  WHITTED_CHECK_##owner(type, name)
#define WHITTED_CHECK_View(type, name)
#define WHITTED_CHECK_Pass(type, name)                                                             \
  ++passRows;                                                                                      \
  WHITTED_CHECK_##type(name)
#define WHITTED_CHECK_bool(name)                                                                   \
  CheckBool(                                                                                       \
    vtkWhittedSettings::name, [&](bool v) { pass->Set##name(v); },                                 \
    [&]() { return pass->Get##name(); });
#define WHITTED_CHECK_NUMBER(type, name)                                                           \
  CheckNumber<type>(                                                                               \
    vtkWhittedSettings::name, pass->Get##name##MinValue(), pass->Get##name##MaxValue(),            \
    [&](type v) { pass->Set##name(v); }, [&]() { return pass->Get##name(); });
#define WHITTED_CHECK_int(name) WHITTED_CHECK_NUMBER(int, name)
#define WHITTED_CHECK_double(name) WHITTED_CHECK_NUMBER(double, name)

  VTK_WHITTED_SETTINGS(WHITTED_CHECK_ROW)

  std::printf("%d settings of the pass checked against vtkWhittedSettings.h, %d failures\n",
    passRows, Failures);
  return passRows > 0 && Failures == 0 ? 0 : 1;
}
