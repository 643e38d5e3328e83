// The deployment key file: generated with mode 0600 and never over an existing file, read back exactly,
// refused when others may read it, and every malformed text rejected with a reason.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "secure/key.hpp"

namespace dhr::secure {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() {
  const fs::path dir = fs::temp_directory_path() /
                       ("dhr_key_test_" + std::to_string(::getpid()) + "_" +
                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

bool same(const Key& a, const Key& b) { return std::equal(a.data(), a.data() + kKeySize, b.data()); }

TEST(SecureKey, GeneratedFileIsPrivateLoadsBackAndIsNeverOverwritten) {
  const fs::path dir = temp_dir();
  const std::string path = (dir / "dhr.key").string();
  ASSERT_EQ(generate_key_file(path), std::nullopt);
  struct stat st {};
  ASSERT_EQ(::stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  std::string error;
  const std::optional<Key> key = load_key_file(path, &error);
  ASSERT_TRUE(key) << error;
  const std::optional<Key> again = load_key_file(path, &error);
  ASSERT_TRUE(again);
  EXPECT_TRUE(same(*key, *again));
  // A second generation refuses, and the key stays.
  const std::optional<std::string> refused = generate_key_file(path);
  ASSERT_TRUE(refused);
  EXPECT_NE(refused->find("exists"), std::string::npos) << *refused;
  EXPECT_TRUE(same(*load_key_file(path, &error), *key));
  // Two generated keys differ.
  ASSERT_EQ(generate_key_file((dir / "other.key").string()), std::nullopt);
  EXPECT_FALSE(same(*load_key_file((dir / "other.key").string(), &error), *key));
  fs::remove_all(dir);
}

TEST(SecureKey, FilesOthersMayReadOrThatAreMissingAreRefused) {
  const fs::path dir = temp_dir();
  const std::string path = (dir / "dhr.key").string();
  ASSERT_EQ(generate_key_file(path), std::nullopt);
  ASSERT_EQ(::chmod(path.c_str(), 0644), 0);
  std::string error;
  EXPECT_FALSE(load_key_file(path, &error));
  EXPECT_NE(error.find("chmod 600"), std::string::npos) << error;
  EXPECT_FALSE(load_key_file((dir / "missing.key").string(), &error));
  EXPECT_NE(error.find("cannot read"), std::string::npos) << error;
  EXPECT_FALSE(load_key_file(dir.string(), &error));  // a directory
  EXPECT_NE(error.find("not a regular file"), std::string::npos) << error;
  fs::remove_all(dir);
}

TEST(SecureKey, TextRoundTripsAndMalformedTextIsRejected) {
  const Key key = Key::random();
  std::string error;
  const std::optional<Key> parsed = parse_key("# a comment\n\n" + format_key(key) + "  \r\n", &error);
  ASSERT_TRUE(parsed) << error;
  EXPECT_TRUE(same(*parsed, key));
  const std::string good = format_key(key);
  const std::string hex = good.substr(good.find(' ') + 1, 64);
  for (const auto& [text, reason] : std::initializer_list<std::pair<std::string, std::string>>{
           {"", "no key"},
           {"# only a comment\n", "no key"},
           {"dhr-xr-key-2 " + hex, "expected"},
           {"dhr-xr-key-1" + hex, "expected"},
           {"dhr-xr-key-1 " + hex.substr(2), "62 hex digits"},
           {"dhr-xr-key-1 " + hex + "00", "66 hex digits"},
           {"dhr-xr-key-1 " + hex.substr(1) + "g", "not a hex digit"},
           {good + good, "more than one key"},
           {std::string("dhr-xr-key-1 ") + std::string(64, '\0'), "not a hex digit"},
       }) {
    SCOPED_TRACE(reason);
    error.clear();
    EXPECT_FALSE(parse_key(text, &error));
    EXPECT_NE(error.find(reason), std::string::npos) << error;
  }
}

}  // namespace
}  // namespace dhr::secure
