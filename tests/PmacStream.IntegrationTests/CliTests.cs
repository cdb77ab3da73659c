using PmacStream.Cli;

namespace PmacStream.IntegrationTests;

public class CliTests
{
    [Fact]
    public void Exit_codes_follow_the_convention()
    {
        CliGlobals.Ok.Should().Be(0);
        CliGlobals.Failed.Should().Be(1);
        CliGlobals.UsageOrIo.Should().Be(2);
    }
}
