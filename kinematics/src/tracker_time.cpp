// Time stamps of tracker files: seconds, ISO 8601, yyyymmddHHMMSS.
#include "tracker_internal.h"

#include <string_view>

namespace ramtk::kinematics::tracker_detail {
namespace {

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
long long DaysFromCivil(long long y, int m, int d) {
  y -= m <= 2 ? 1 : 0;
  const long long era = (y >= 0 ? y : y - 399) / 400;
  const long long yoe = y - era * 400;
  const long long doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const long long doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + doe - 719468;
}

int DaysInMonth(long long y, int m) {
  static const int kDays[] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (y % 4 == 0 && y % 100 != 0) || y % 400 == 0;
  return m == 2 && leap ? 29 : kDays[m - 1];
}

bool Digits(std::string_view s, std::size_t pos, std::size_t count, int* value) {
  if (pos + count > s.size()) return false;
  int v = 0;
  for (std::size_t i = pos; i < pos + count; ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    v = v * 10 + (s[i] - '0');
  }
  *value = v;
  return true;
}

// Calendar fields to unix seconds (UTC); false when a field is out of range.
bool CivilToStamp(int y, int mo, int d, int h, int mi, int s, Stamp* out) {
  if (mo < 1 || mo > 12 || d < 1 || d > DaysInMonth(y, mo) || h > 23 || mi > 59 || s > 60) return false;
  out->whole = DaysFromCivil(y, mo, d) * 86400 + h * 3600 + mi * 60 + s;
  out->fraction = 0.0;
  return true;
}

}  // namespace

bool ParseCompact(std::string_view s, Stamp* out) {
  int y, mo, d, h, mi, sec;
  if (s.size() != 14) return false;
  if (!Digits(s, 0, 4, &y) || !Digits(s, 4, 2, &mo) || !Digits(s, 6, 2, &d) || !Digits(s, 8, 2, &h) ||
      !Digits(s, 10, 2, &mi) || !Digits(s, 12, 2, &sec)) {
    return false;
  }
  return CivilToStamp(y, mo, d, h, mi, sec, out);
}

bool ParseIso8601(std::string_view s, Stamp* out) {
  int y, mo, d, h, mi, sec;
  if (s.size() < 19 || !Digits(s, 0, 4, &y) || s[4] != '-' || !Digits(s, 5, 2, &mo) || s[7] != '-' ||
      !Digits(s, 8, 2, &d) || (s[10] != 'T' && s[10] != ' ') || !Digits(s, 11, 2, &h) || s[13] != ':' ||
      !Digits(s, 14, 2, &mi) || s[16] != ':' || !Digits(s, 17, 2, &sec)) {
    return false;
  }
  if (!CivilToStamp(y, mo, d, h, mi, sec, out)) return false;
  std::size_t pos = 19;
  if (pos < s.size() && (s[pos] == '.' || s[pos] == ',')) {
    // As an integer over a power of ten: .125 is exactly 0.125.
    long long digits = 0, scale = 1;
    for (++pos; pos < s.size() && s[pos] >= '0' && s[pos] <= '9'; ++pos) {
      if (scale < 1000000000000000000LL / 10) {  // beyond 1e-17 s the digits carry nothing
        digits = digits * 10 + (s[pos] - '0');
        scale *= 10;
      }
    }
    if (scale == 1) return false;
    out->fraction = static_cast<double>(digits) / static_cast<double>(scale);
  }
  if (pos == s.size()) return true;
  if (s[pos] == 'Z' || s[pos] == 'z') return pos + 1 == s.size();
  if (s[pos] != '+' && s[pos] != '-') return false;
  const int sign = s[pos] == '-' ? -1 : 1;
  int oh = 0, om = 0;
  if (!Digits(s, pos + 1, 2, &oh)) return false;
  pos += 3;
  if (pos < s.size() && s[pos] == ':') ++pos;
  if (pos < s.size() && !Digits(s, pos, 2, &om)) return false;
  if (pos < s.size()) pos += 2;
  if (pos != s.size() || oh > 23 || om > 59) return false;
  out->whole -= sign * (oh * 3600 + om * 60);  // local = UTC + offset
  return true;
}

bool LooksLikeRoundedCompact(const std::string& text, char decimal) {
  double v = 0.0;
  return text.size() != 14 && ToDouble(text, decimal, &v) && v >= 1e13 && v < 1e14;
}

TimeForm DecideTimeForm(const std::string& form, const std::string& first, char decimal) {
  if (form == "seconds") return TimeForm::kSeconds;
  if (form == "iso8601") return TimeForm::kIso8601;
  if (form == "yyyymmddhhmmss") return TimeForm::kCompact;
  Stamp s;
  if (ParseIso8601(first, &s)) return TimeForm::kIso8601;
  if (ParseCompact(first, &s)) return TimeForm::kCompact;
  if (LooksLikeRoundedCompact(first, decimal)) return TimeForm::kUnusable;
  return TimeForm::kSeconds;
}

}  // namespace ramtk::kinematics::tracker_detail
