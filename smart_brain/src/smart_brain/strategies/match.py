"""match: the robot's match strategy, chosen by ~match_variant (2008: Logion's ball harvest,
2009: the column builder), so every robot launches with strategy:=match."""
import rospy

from smart_brain.strategy import Strategy, StrategyError, register

VARIANTS = {'2008': 'match2008', '2009': 'match2009'}


@register
class MatchStrategy(Strategy):
    name = 'match'
    description = "the robot's match strategy (~match_variant: %s)" % ', '.join(sorted(VARIANTS))

    def __init__(self):
        self._impl = None

    @classmethod
    def configured_in(cls, brain):
        return brain.has('match_variant')  # it has no block: ~match is the brain's own (the match timer)

    def read_config(self, brain, table):
        """~match_variant, then the variant's own parameters."""
        from smart_brain import strategy as strategies
        variant = str(brain.value('match_variant', '', str, allowed=sorted(VARIANTS), meaning='the match strategy: %s'
                                  % ', '.join('%s (%s)' % (k, v) for k, v in sorted(VARIANTS.items()))))
        if variant not in VARIANTS:
            raise StrategyError("parameter %s = '%s': allowed values: %s"
                                % (brain.qualified('match_variant'), variant, ', '.join(sorted(VARIANTS))))
        self._impl = strategies.create(VARIANTS[variant], brain, table)

    @property
    def impl(self):
        if self._impl is None:
            raise StrategyError('strategy match: its parameters were not read (read_config)')
        return self._impl

    @property
    def required_devices(self):
        return self.impl.required_devices

    @property
    def required_topics(self):
        return self.impl.required_topics

    def initialize(self):
        rospy.loginfo('brain: match strategy variant %s', self.impl.name)
        self.impl.initialize()

    def execute(self):
        return self.impl.execute()

    def finalize(self):
        self.impl.finalize()

    def stop(self):
        self.impl.stop()

    def funny_action(self):
        self.impl.funny_action()
