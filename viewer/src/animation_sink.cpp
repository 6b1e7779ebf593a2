// The animation sink (animation_sink.hpp).
#include <mbd/viewer/animation_sink.hpp>

namespace mbd::viewer {

namespace {

class AnimationSink : public OutputSink {
public:
    AnimationSink(const Model& model, std::string path, AnimationOptions options)
        : model_(model), path_(std::move(path)), options_(std::move(options)) {
        animation_format(path_);  // a bad name fails before the run
    }

    void begin(const std::vector<std::string>& columns) override {
        table_.source = "the run's rows (" + path_ + ")";
        table_.columns = columns;
        table_.values.clear();
        match_pose_columns(model_, table_);  // the scene's poses are in the rows
    }
    void row(const std::vector<double>& values) override {
        table_.values.insert(table_.values.end(), values.begin(), values.end());
    }
    void end() override { export_animation(model_, table_, path_, options_); }

private:
    const Model& model_;
    std::string path_;
    AnimationOptions options_;
    MotionTable table_;
};

}  // namespace

std::unique_ptr<OutputSink> make_animation_sink(const Model& model, const std::string& path,
                                                const AnimationOptions& options) {
    return std::make_unique<AnimationSink>(model, path, options);
}

}  // namespace mbd::viewer
