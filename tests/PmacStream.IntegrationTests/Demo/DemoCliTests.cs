using System.Text.RegularExpressions;

namespace PmacStream.IntegrationTests.Demo;

public class DemoCliTests
{
    [Fact]
    public void Demo_splits_streams_into_the_simulator_and_executes_every_block()
    {
        // A faster clock than the default keeps the test short; the logic is the same.
        var (code, stdout, stderr) = CliRun.InProcess("demo", "--sim-speed", "200x");
        code.Should().Be(0, stderr + stdout);
        var last = stdout.TrimEnd().Split('\n').Last().Trim();
        var m = Regex.Match(last, @"^executed (\d+) of (\d+) blocks$");
        m.Success.Should().BeTrue($"the demo ends with 'executed N of N blocks', not '{last}'");
        m.Groups[1].Value.Should().Be(m.Groups[2].Value);
        int.Parse(m.Groups[2].Value).Should().Be(3207, "samples/demo.nc has 3207 motion blocks by the splitter's count");
        stdout.Should().Contain("split into 4 chunks");
        stdout.Should().Contain("chunk 2 downloaded at M0=");
        stdout.Should().Contain("chunk 4/4");
    }
}
