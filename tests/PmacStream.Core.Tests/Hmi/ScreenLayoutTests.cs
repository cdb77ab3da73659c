using PmacStream.Hmi;
using PmacStream.Jobs;
using PmacStream.Pmac;
using PmacStream.Sim;

namespace PmacStream.Core.Tests.Hmi;

public sealed class ScreenLayoutTests
{
    private static bool Overlap(LayoutBox a, LayoutBox b) =>
        a.X < b.X + b.Width && b.X < a.X + a.Width && a.Y < b.Y + b.Height && b.Y < a.Y + a.Height;

    [Fact]
    public void No_two_controls_of_one_container_overlap_and_all_fit()
    {
        var controls = ScreenSketch.Controls;
        foreach (var group in controls.GroupBy(c => c.Parent))
        {
            var items = group.ToList();
            for (var i = 0; i < items.Count; i++)
            {
                for (var j = i + 1; j < items.Count; j++)
                {
                    Overlap(items[i].Box, items[j].Box).Should().BeFalse($"{items[i].Name} and {items[j].Name} overlap");
                }

                var box = items[i].Box;
                if (group.Key is { } parent)
                {
                    var p = controls.Single(c => c.Name == parent).Box;
                    (box.X + box.Width).Should().BeLessThanOrEqualTo(p.Width, $"{items[i].Name} fits in {parent}");
                    (box.Y + box.Height).Should().BeLessThanOrEqualTo(p.Height, $"{items[i].Name} fits in {parent}");
                }
                else
                {
                    (box.X + box.Width).Should().BeLessThanOrEqualTo(HmiLayout.ClientWidth, items[i].Name);
                    (box.Y + box.Height).Should().BeLessThanOrEqualTo(HmiLayout.ClientHeight, items[i].Name);
                }
            }
        }
    }

    [Fact]
    public void The_sketch_lists_every_control_the_form_places()
    {
        // MainForm.cs cannot be compiled here (no Windows Desktop targeting pack): check by its source that the
        // sketch and the form place the same controls in the same layout boxes.
        var form = File.ReadAllText(Path.Combine(RepoRoot.Path, "src", "PmacStream.WinForms", "MainForm.cs"));
        var placed = System.Text.RegularExpressions.Regex.Matches(form, @"Place\((\w+), HmiLayout\.(\w+)")
            .Select(m => (Name: m.Groups[1].Value, Box: m.Groups[2].Value)).ToList();
        placed.Should().HaveCountGreaterThan(40);
        var sketched = ScreenSketch.Controls.Select(c => c.Name).ToHashSet();
        foreach (var (name, box) in placed)
        {
            sketched.Should().Contain(name, $"the form places {name} at HmiLayout.{box}");
            var expected = typeof(HmiLayout).GetField(box)!.GetValue(null);
            ScreenSketch.Controls.Single(c => c.Name == name).Box.Should().Be((LayoutBox)expected!, name);
        }
    }
}

/// <summary>Draws the screen in a realistic state: the sample program checked, split and half way through a job on the simulator.</summary>
public sealed class ScreenSketchTests : IAsyncLifetime
{
    private readonly string _dir = Path.Combine(Path.GetTempPath(), "pmacstream-hmi-sketch-" + Guid.NewGuid().ToString("N"));

    public Task InitializeAsync()
    {
        Directory.CreateDirectory(_dir);
        return Task.CompletedTask;
    }

    public Task DisposeAsync()
    {
        Directory.Delete(_dir, recursive: true);
        return Task.CompletedTask;
    }

    [Theory]
    [InlineData(HmiLanguage.English, "hmi-screen")]
    [InlineData(HmiLanguage.Chinese, "hmi-screen-zh")]
    public async Task Draws_the_screen_mid_job(HmiLanguage language, string name)
    {
        var source = Path.Combine(_dir, "demo.nc");
        File.Copy(RepoRoot.DemoProgram, source);
        using var sim = new PmacStream.Sim.PmacSimulator();
        var backend = new CoreHmiBackend(new JobService(new JobServiceOptions
        {
            Simulator = _ => Task.FromResult(new SimulatorLink(
                new InProcessConnection(sim.OpenPort("hmi"), "simulator (in-process)"),
                new SimTimeProvider(sim, new DateTimeOffset(2026, 1, 1, 0, 0, 0, TimeSpan.Zero)))),
            JobDatabase = Path.Combine(_dir, "jobs.db"),
        }));
        var view = new FakeView { Language = language };
        var sink = new HmiLogSink();
        var log = new Serilog.LoggerConfiguration().WriteTo.Hmi(sink).CreateLogger().ForContext<MainPresenter>();
        await using var p = new MainPresenter(view, backend, sink, log);

        async Task Do(Action a)
        {
            a();
            await p.WhenIdleAsync();
        }

        await Do(() => view.ChooseFile(source));
        await Do(view.ClickConnect);
        await Do(view.ClickCheck);
        await Do(view.ClickSplit);
        await Do(() => view.SelectChunk(1));
        await Do(view.ClickExecute);
        while (view.ExecutingLine < 1480 && p.JobActive)
        {
            await p.TickAsync();
            sim.Advance(TimeSpan.FromSeconds(0.5));
        }

        view.Errors.Should().BeEmpty();
        view.ChunkFiles.Should().HaveCount(4, "3225 lines in chunks of at most 1000 blocks");
        view.ExecutingLine.Should().BeInRange(1480, 1500);
        view.Status.CurrentFile.Should().StartWith("2/4");
        var title = $"{view.Texts[TextId.Title]} – demo.nc";
        var html = ScreenSketch.Render(view, title, programTopLine: view.ExecutingLine - 10, chunkTopLine: 1, selectedChunk: 1);

        html.Should().Contain(System.Net.WebUtility.HtmlEncode(view.Texts[TextId.Execute]));
        html.Should().Contain("row exe\"><span class=\"n\">" + view.ExecutingLine + "</span>");
        html.Should().Contain("M0==", "the chunk lines show the tracking markers the splitter wrote");
        if (language == HmiLanguage.Chinese)
        {
            html.Should().Contain("程序段执行").And.Contain("断点续加工");
        }

        // PMACSTREAM_HMI_SKETCH_DIR=DIR makes the test leave the page there for headless chromium.
        if (Environment.GetEnvironmentVariable("PMACSTREAM_HMI_SKETCH_DIR") is { Length: > 0 } outDir)
        {
            File.WriteAllText(Path.Combine(outDir, name + ".html"), html);
        }
    }
}
