// Job requests of `megavox serve` (serve/job_request.h) as a client may send them: each kind's fields taken,
// every bad field refused with a message naming its JSON key, and failures from the library and the C API
// reworded in the service's terms (serve/job_words.h). No device: parsing only.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "serve_error.h"
#include "job_request.h"
#include "job_words.h"

namespace {

using mv::serve::JobKind;
using mv::serve::JobRequest;
using mv::serve::parse_job_request;

// The refusal's message, or "" when the body parses.
std::string refusal(const std::string& body) {
  try {
    parse_job_request(body);
  } catch (const mv::serve::ServeError& e) {
    return e.what();
  }
  return "";
}

#define EXPECT_REFUSED(body, words)                                     \
  do {                                                                  \
    const std::string m = refusal(body);                                \
    EXPECT_NE(m.find(words), std::string::npos) << (body) << " -> " << m; \
  } while (0)

TEST(ServeJobRequest, PointsJob) {
  const JobRequest r = parse_job_request(R"({"kind":"points","input":"scan.las"})");
  EXPECT_EQ(r.kind, JobKind::points);
  EXPECT_EQ(r.input, "scan.las");
  EXPECT_EQ(r.format, "mvx");
  EXPECT_EQ(r.depth, 0u);
  const JobRequest t = parse_job_request(R"({"kind":"points","input":"a.ply","format":"3dtiles","depth":9,"max_node_points":100})");
  EXPECT_EQ(t.format, "3dtiles");
  EXPECT_EQ(t.depth, 9u);
  EXPECT_EQ(t.max_node_points, 100u);
  EXPECT_EQ(t.tiles_version, "1.1");
  const JobRequest v = parse_job_request(
      R"({"kind":"points","input":"a.laz","format":"3dtiles","tiles_version":"1.0","crs":"EPSG:32610",)"
      R"("bounds":[1,2,3,4.5,5,6]})");
  EXPECT_EQ(v.tiles_version, "1.0");
  EXPECT_EQ(v.crs, "EPSG:32610");
  ASSERT_TRUE(v.bounds);
  EXPECT_EQ((*v.bounds)[3], 4.5);
}

TEST(ServeJobRequest, PointsRefusals) {
  EXPECT_REFUSED(R"({"kind":"points","input":"a.ply","format":"svdag"})", "\"format\" 'svdag': choose mvx, 3dtiles");
  EXPECT_REFUSED(R"({"kind":"points","input":"a.ply","depth":22})", "\"depth\" must be from 0 to 21");
  EXPECT_REFUSED(R"({"kind":"points","input":"a.ply","depth":-1})", "\"depth\" must be from 0 to 21");
  EXPECT_REFUSED(R"({"kind":"points","input":"a.ply","max_node_points":0})", "\"max_node_points\" must be from 1");
  EXPECT_REFUSED(R"({"kind":"points","input":"a.ply","max_node_points":"500"})", "\"max_node_points\" must be an integer");
  EXPECT_REFUSED(R"({"kind":"points","input":"a.ply","resolution":64})", "a points job takes no \"resolution\"");
  EXPECT_REFUSED(R"({"kind":"points","scene":"00ff"})", "a points job takes no \"scene\"");
  EXPECT_REFUSED(R"({"kind":"build","input":"a.ply","format":"3dtiles"})", "choose svo, svdag, ussvdag, ssvdag");
  EXPECT_REFUSED(R"({"kind":"points","input":"a.las","format":"3dtiles","tiles_version":"2.0"})", "choose 1.1, 1.0");
  EXPECT_REFUSED(R"({"kind":"points","input":"a.las","crs":"EPSG:4978"})", "apply to \"format\": \"3dtiles\" only");
  EXPECT_REFUSED(R"({"kind":"points","input":"a.las","format":"3dtiles","crs":""})", "\"crs\" must be EPSG:N or a WKT");
  EXPECT_REFUSED(R"({"kind":"points","input":"a.las","bounds":[1,2,3]})", "\"bounds\" must be an array of six numbers");
  EXPECT_REFUSED(R"({"kind":"points","input":"a.las","bounds":[1,2,3,0,5,6]})", "each minimum at most its maximum");
  EXPECT_REFUSED(R"({"kind":"build","input":"a.ply","bounds":[0,0,0,1,1,1]})", "a build job takes no \"bounds\"");
}

TEST(ServeJobRequest, MaskJob) {
  const JobRequest r = parse_job_request(R"({"kind":"mask","input":"p.png","rect":[1,2,30,40]})");
  EXPECT_EQ(r.kind, JobKind::mask);
  ASSERT_TRUE(r.rect);
  EXPECT_EQ((*r.rect)[0], 1u);
  EXPECT_EQ((*r.rect)[3], 40u);
  EXPECT_EQ(r.iterations, 5u);
  EXPECT_EQ(r.erode, 2u);
  const JobRequest s = parse_job_request(R"({"kind":"mask","input":"p.png","seeds":"t.png","model":"m.mvm","iterations":2,"erode":0})");
  EXPECT_FALSE(s.rect);
  EXPECT_EQ(s.seeds, "t.png");
  EXPECT_EQ(s.model, "m.mvm");
  EXPECT_EQ(s.iterations, 2u);
  EXPECT_EQ(s.erode, 0u);
}

TEST(ServeJobRequest, MaskRefusals) {
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png"})", "a mask job needs a start");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":[1,2,3]})", "\"rect\" must be an array of four integers");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":"1,2,3,4"})", "\"rect\" must be an array of four integers");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":[1,2,3,4,5]})", "\"rect\" must be an array of four integers");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":[-1,2,3,4]})", "x and y must be from 0");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":[1,2,0,4]})", "w and h must be from 1");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":[1,2,3,4.5]})", "\"rect\" must be an integer");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":[1,2,3,268435457]})", "w and h must be from 1 to 268435456");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","seeds":7})", "\"seeds\" must be a string");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","model":["m.mvm"]})", "\"model\" must be a string");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":[0,0,1,1],"iterations":0})", "\"iterations\" must be from 1 to 100");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":[0,0,1,1],"erode":33})", "\"erode\" must be from 0 to 32");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":[0,0,1,1],"width":64})", "a mask job takes no \"width\"");
  EXPECT_REFUSED(R"({"kind":"build","input":"a.ply","rect":[0,0,1,1]})", "a build job takes no \"rect\"");
}

TEST(ServeJobRequest, RenderDefaultsAreTheCli) {
  const JobRequest r = parse_job_request(R"({"kind":"render","scene":"00ff"})");
  EXPECT_EQ(r.width, 1920u);  // RenderOptions' defaults, as `megavox render` draws
  EXPECT_EQ(r.height, 1080u);
  EXPECT_FALSE(r.eye);
  EXPECT_EQ(r.fov, 40);
}

TEST(ServeJobRequest, RenderCamera) {
  const JobRequest r = parse_job_request(R"({"kind":"render","scene":"00ff","eye":[1,2,3],"target":[0,0.5,0],"up":[0,0,1],"fov":30.5})");
  ASSERT_TRUE(r.eye && r.target);
  EXPECT_EQ((*r.eye)[2], 3);
  EXPECT_EQ((*r.target)[1], 0.5);
  EXPECT_EQ(r.up[2], 1);
  EXPECT_EQ(r.fov, 30.5);
  EXPECT_EQ(refusal(R"({"kind":"render","scene":"00ff","eye":[1,2,3]})"), "");  // target: the model's centre
  EXPECT_EQ(refusal(R"({"kind":"render","scene":"00ff","fov":90})"), "");       // the view, at this fov
}

TEST(ServeJobRequest, RenderCameraRefusals) {
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","eye":[1,2]})", "\"eye\" must be an array of three numbers");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","eye":{"x":1}})", "\"eye\" must be an array of three numbers");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","eye":[1,"2",3]})", "\"eye\" must be a number");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","eye":[1,2,1e999]})", "malformed JSON");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","target":[1,2,3]})", "\"target\" and \"up\" go with \"eye\"");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","up":[0,0,1]})", "\"target\" and \"up\" go with \"eye\"");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","eye":[1,1,1],"target":[1,1,1]})", "\"eye\" and \"target\" must differ");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","eye":[0,0,0],"target":[0,5,0]})", "\"up\" must not point along");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","eye":[1,0,0],"up":[0,0,0]})", "\"up\" must not be [0, 0, 0]");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","fov":0})", "\"fov\" must lie between 0 and 180");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","fov":180})", "\"fov\" must lie between 0 and 180");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","fov":"wide"})", "\"fov\" must be a number");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","width":0})", "\"width\" must be from 1 to 8192");
  EXPECT_REFUSED(R"({"kind":"render","scene":"s","cube":64})", "a render job takes no \"cube\"");
}

TEST(ServeJobRequest, BuildCube) {
  EXPECT_FALSE(parse_job_request(R"({"kind":"build","input":"a.ply"})").cube);  // the C API's default
  EXPECT_EQ(parse_job_request(R"({"kind":"build","input":"a.ply","cube":0})").cube, 0u);  // in core
  EXPECT_EQ(parse_job_request(R"({"kind":"build","input":"a.ply","cube":256})").cube, 256u);
  EXPECT_REFUSED(R"({"kind":"build","input":"a.ply","cube":4})", "\"cube\" must be 0 (always in core) or a power of two from 8");
  EXPECT_REFUSED(R"({"kind":"build","input":"a.ply","cube":100})", "\"cube\" must be 0 (always in core) or a power of two");
  EXPECT_REFUSED(R"({"kind":"build","input":"a.ply","cube":4194304})", "\"cube\" must be from 0 to 2097152");
}

TEST(ServeJobRequest, KindsAndKeys) {
  EXPECT_REFUSED(R"({"input":"a.ply"})", "\"kind\" is missing (build, render, points, mask or open)");
  EXPECT_REFUSED(R"({"kind":"bake"})", "choose build, render, points, mask");
  EXPECT_REFUSED(R"({"kind":"mask","input":"p.png","rect":[0,0,1,1],"colour":1})", "unknown key \"colour\"");
  EXPECT_REFUSED(R"([1,2])", "the body must be a JSON object");
}

TEST(ServeJobRequest, OpenJob) {
  const JobRequest r = mv::serve::parse_job_request(R"({"kind":"open","input":"scans/city.mvx"})");
  EXPECT_EQ(r.kind, JobKind::open);
  EXPECT_EQ(r.input, "scans/city.mvx");
  EXPECT_REFUSED(R"({"kind":"open"})", "an open job needs \"input\"");
  EXPECT_REFUSED(R"({"kind":"open","input":"a.mvx","resolution":64})", "an open job takes no \"resolution\"");
  EXPECT_REFUSED(R"({"kind":"open","scene":"00ab"})", "an open job takes no \"scene\"");
  EXPECT_THROW(mv::serve::job_request_from_query({{"kind", "open"}}), mv::serve::ServeError);
  EXPECT_EQ(mv::serve::kind_name(JobKind::open), "open");
}

TEST(ServeJobRequest, UploadQuery) {
  const std::multimap<std::string, std::string> mask = {{"kind", "mask"}, {"rect", "4,5,20,10"}, {"name", "p.png"}};
  const JobRequest m = mv::serve::job_request_from_query(mask);
  ASSERT_TRUE(m.rect);
  EXPECT_EQ((*m.rect)[2], 20u);
  const std::multimap<std::string, std::string> render = {{"kind", "render"}, {"eye", "1,2.5,-3"}, {"fov", "35"}};
  const JobRequest r = mv::serve::job_request_from_query(render);
  ASSERT_TRUE(r.eye);
  EXPECT_EQ((*r.eye)[1], 2.5);
  EXPECT_EQ(r.fov, 35);
  const std::multimap<std::string, std::string> points = {{"kind", "points"}, {"format", "3dtiles"}, {"depth", "7"}};
  EXPECT_EQ(mv::serve::job_request_from_query(points).depth, 7u);
  const std::multimap<std::string, std::string> boxed = {{"kind", "points"}, {"bounds", "0,0,0,1,2,3"}, {"format", "3dtiles"}, {"tiles_version", "1.0"}};
  const JobRequest b = mv::serve::job_request_from_query(boxed);
  ASSERT_TRUE(b.bounds);
  EXPECT_EQ((*b.bounds)[5], 3.0);
  EXPECT_EQ(b.tiles_version, "1.0");
  for (const auto& [key, value] : std::multimap<std::string, std::string>{
           {"rect", "1,2,3"}, {"rect", "1,2,3,x"}, {"rect", "1,2,3,4,5"}, {"eye", "1,2,nan"}, {"fov", "40deg"}, {"depth", "-1"}}) {
    const std::string kind = key == "rect" ? "mask" : key == "depth" ? "points" : "render";
    EXPECT_THROW(mv::serve::job_request_from_query({{"kind", kind}, {key, value}}), mv::serve::ServeError) << key << "=" << value;
  }
}

TEST(ServeJobWords, LibraryTermsBecomeJobKeys) {
  using mv::serve::in_job_terms;
  EXPECT_EQ(in_job_terms("raise the cube size to 512 or more, or lower the resolution"),
            "raise \"cube\" to 512 or more, or lower \"resolution\"");
  EXPECT_EQ(in_job_terms("over the host memory budget 2 GiB; raise the host memory budget"),
            "over the server's host memory per job 2 GiB; raise the server's host memory per job");
  EXPECT_EQ(in_job_terms("the grid origin, the node point limit, the device memory budget."),
            "\"grid_origin\", \"max_node_points\", the server's device memory per job.");
  // terms it has no key for, and terms inside longer words, stay as they are
  EXPECT_EQ(in_job_terms("the bounds and xthe cube size and the resolutions"),
            "the bounds and xthe cube size and the resolutions");
}

}  // namespace
