!> The energy balance of a run: its terms (energies_type), their total and residual, the
!> guard's energy scale, and the record checkpoints keep. docs/output.md defines each term;
!> mpm_solver sums them step by step.
module mpm_energy
    use mpm_kinds, only: wp
    use mpm_material, only: nwork_kinds, work_plastic, work_viscous
    use mpm_kernel_stress, only: nstress_sums
    use mpm_kernel_nodal, only: nnodal_sums, nodal_damping, nodal_friction, nodal_boundary, &
        nodal_faces, nodal_absorbed, nodal_rigid
    implicit none
    private
    public :: energies_type, energy_total, energy_residual, energy_scale, energy_record, &
        energies_from_record, nenergy_record, step_energies

    integer, parameter :: nenergy_record = 13 + nwork_kinds
        !! values of energy_record (the `energy` attribute of a checkpoint's run record)

    !> Energy terms of a run [J] (per metre of thickness in 2D [J/m]), since the start of the
    !> balance (start_energy_balance). They close: energy_residual, kinetic + elastic +
    !> potential + plastic + viscous + damping + friction + boundary + transfer - loads -
    !> initial, is the energy the time integration created (> 0) or lost (< 0).
    !> docs/output.md defines each.
    type :: energies_type
        real(wp) :: kinetic = 0.0_wp
            !! sum 1/2 m v^2 [J]
        real(wp) :: strain = 0.0_wp
            !! work done by the stresses since the start, all materials [J]
        real(wp) :: elastic = 0.0_wp
            !! elastic energy stored in the particles now, sum V w(sigma) [J]
        real(wp) :: potential = 0.0_wp
            !! gravitational potential relative to the start, - sum m g . u [J], summed step
            !! by step from the moves
        real(wp) :: plastic = 0.0_wp
            !! plastic dissipation: work of the stresses of plastic materials minus the change
            !! of their stored elastic energy [J]
        real(wp) :: viscous = 0.0_wp
            !! viscous dissipation: the same for viscous materials [J]
        real(wp) :: damping = 0.0_wp
            !! energy removed by the `damping` of the case (local or kinetic) [J]
        real(wp) :: friction = 0.0_wp
            !! kinetic energy removed by the friction of frictional faces and the terrain [J]
        real(wp) :: loads = 0.0_wp
            !! work of the prescribed body forces of drivers (not gravity) [J]
        real(wp) :: initial = 0.0_wp
            !! kinetic + elastic energy at the start of the balance [J]
        real(wp) :: supplied = 0.0_wp
            !! largest |work of gravity| + |work of loads| so far (energy_scale) [J]
        real(wp) :: stored(nwork_kinds) = 0.0_wp
            !! the elastic energy by work kind of the materials (`work_*` of mpm_material) [J]
        real(wp) :: boundary = 0.0_wp
            !! kinetic energy stopped by the fixed components of the faces and the normal
            !! constraint of the contacts: 1/2 m v^2 of the normal velocity a node brings into
            !! the step (APIC, PIC); with FLIP what the contacts' normal impulses take from the
            !! particles [J]
        real(wp) :: transfer = 0.0_wp
            !! kinetic energy lost in the particle-grid transfers: particles minus nodes after
            !! P2G, nodes after the nodal update minus particles after G2P (APIC, PIC); with a
            !! FLIP-PIC blend what its PIC part takes from the FLIP velocities [J]
    end type energies_type

contains

    !> Kinetic + elastic + potential + dissipated energy - work of the loads [J]: constant
    !> (equal to `initial`) for an exact integrator.
    pure real(wp) function energy_total(e)
        type(energies_type), intent(in) :: e
            !! energy terms
        energy_total = e%kinetic + e%elastic + e%potential + e%plastic + e%viscous &
            + e%damping + e%friction - e%loads
        energy_total = energy_total + e%boundary + e%transfer
    end function energy_total

    !> The energy the discretisation created since the start (> 0) or lost (< 0) [J].
    pure real(wp) function energy_residual(e)
        type(energies_type), intent(in) :: e
            !! energy terms
        energy_residual = energy_total(e) - e%initial
    end function energy_residual

    !> The energy scale of a run for the blow-up guard [J]: initial kinetic + elastic energy
    !> and the largest |work of gravity| + |work of loads| so far (an undamped body swings
    !> back to where gravity did no net work: what it was given is the largest), at least
    !> `floor`.
    pure real(wp) function energy_scale(e, floor)
        type(energies_type), intent(in) :: e
            !! energy terms
        real(wp), intent(in) :: floor
            !! smallest scale [J]
        energy_scale = max(e%initial + e%supplied, floor)
    end function energy_scale

    !> The energy terms as one array (checkpoints), in the order of energies_type.
    pure function energy_record(e) result(r)
        type(energies_type), intent(in) :: e
            !! energy terms
        real(wp) :: r(nenergy_record)
        r = [e%kinetic, e%strain, e%elastic, e%potential, e%plastic, e%viscous, e%damping, &
            e%friction, e%loads, e%initial, e%supplied, e%stored, e%boundary, e%transfer]
    end function energy_record

    !> The energy terms of an energy_record.
    pure function energies_from_record(r) result(e)
        real(wp), intent(in) :: r(nenergy_record)
            !! energy_record
        type(energies_type) :: e
        e = energies_type(r(1), r(2), r(3), r(4), r(5), r(6), r(7), r(8), r(9), r(10), &
            r(11), r(12:11 + nwork_kinds))
        e%boundary = r(12 + nwork_kinds)
        e%transfer = r(13 + nwork_kinds)
    end function energies_from_record


    !> The energy terms after a step from those before and the sums of the step (over all
    !> images): kinetic energy, change of the potential, work of the loads, the stress sums
    !> (nstress_sums), the nodal sums (nnodal_sums), the kinetic energy of the nodes after
    !> P2G and after the nodal update, and the kinetic energy a FLIP-PIC blend's PIC part took.
    pure function step_energies(before, sums, grid_velocities) result(e)
        type(energies_type), intent(in) :: before
            !! terms at the start of the step
        real(wp), intent(in) :: sums(:)
            !! the sums of the step [J]
        logical, intent(in) :: grid_velocities
            !! G2P gives the particles the nodal velocities (APIC, PIC): the kinetic energy
            !! the nodes lose to the constraints and the transfers is theirs. FLIP adds the
            !! nodal accelerations to the particle velocities instead: a held component (zero
            !! acceleration) leaves them as they are, and the particles keep the velocity the
            !! nodes do not hold; no nodal transfer term is booked (only a blend's loss), and
            !! the friction and boundary sums are the contacts' work on the particles
            !! (contact_particle_work)
        type(energies_type) :: e

        real(wp) :: work(nwork_kinds), stored(nwork_kinds), nodal(nnodal_sums), grid(2), blend

        work = sums(4:3 + nwork_kinds)
        stored = sums(4 + nwork_kinds:3 + nstress_sums)
        nodal = sums(4 + nstress_sums:3 + nstress_sums + nnodal_sums)
        grid = sums(4 + nstress_sums + nnodal_sums:5 + nstress_sums + nnodal_sums)
        blend = sums(6 + nstress_sums + nnodal_sums)
        e = before
        ! the kinetic energy was summed in the G2P pass (nothing changes the velocities after)
        e%kinetic = sums(1)
        e%potential = e%potential + sums(2)
        ! the work of the loads: prescribed forces, then the velocity faces
        e%loads = e%loads + sums(3) + nodal(nodal_faces)
        e%strain = e%strain + sum(work)
        ! the work of a plastic or viscous material that its elastic energy did not take
        e%plastic = e%plastic + work(work_plastic) &
            - (stored(work_plastic) - before%stored(work_plastic))
        e%viscous = e%viscous + work(work_viscous) &
            - (stored(work_viscous) - before%stored(work_viscous))
        e%stored = stored
        e%elastic = sum(stored)
        e%supplied = max(before%supplied, abs(e%potential) + abs(e%loads))
        e%damping = e%damping + nodal(nodal_damping)
        e%friction = e%friction + nodal(nodal_friction)
        ! what the faces stop, what leaves through the absorbing faces, and what the rigid
        ! bodies' constraint takes (FLIP too: the nodal accelerations carry it)
        e%boundary = e%boundary + nodal(nodal_boundary) + nodal(nodal_absorbed) &
            + nodal(nodal_rigid)
        if (.not. grid_velocities) then
            ! a FLIP-PIC blend: the kinetic energy its PIC part took from the FLIP velocities
            ! (0 for FLIP); the FLIP part is booked as FLIP is
            if (blend /= 0.0_wp) e%transfer = e%transfer + blend
            return
        end if
        ! the particles' kinetic energy the P2G projection did not give the nodes, and the
        ! nodes' that G2P did not give back to the particles
        e%transfer = e%transfer + (before%kinetic - grid(1)) + (grid(2) - e%kinetic)
    end function step_energies

end module mpm_energy
