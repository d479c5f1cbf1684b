!> Linear elastic material with the Jaumann (objective) stress rate:
!> `materials[i].type = "linear_elastic"` (or "elastic"), keys `E`, `nu`, `rho`.
module mpm_material_elastic
    use mpm_kinds, only: wp
    use mpm_material, only: material_key_width
    use mpm_elastic_solid, only: elastic_solid_type, elastic_keys, add_elastic_trial
    implicit none
    private
    public :: elastic_material_type, new_elastic_material

    !> Isotropic linear elasticity (Hooke) in rate form; E, nu, rho and the rest of what an
    !> elastic solid knows come from `elastic_solid_type`.
    type, extends(elastic_solid_type) :: elastic_material_type
    contains
        procedure, nopass :: names => elastic_names
        procedure, nopass :: keys => elastic_material_keys
        procedure :: update_stress => elastic_update_stress
        procedure :: update_stress_block => elastic_update_stress_block
    end type elastic_material_type

contains

    !> Names accepted for `type`, the stored one first.
    pure subroutine elastic_names(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=material_key_width) :: "linear_elastic", "elastic"]
    end subroutine elastic_names

    !> Keys of a linear elastic material.
    pure subroutine elastic_material_keys(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = elastic_keys
    end subroutine elastic_material_keys

    !> Construct a linear elastic material from E, nu and rho.
    pure subroutine new_elastic_material(mat, name, young, poisson, density)
        type(elastic_material_type), intent(out) :: mat
            !! the material
        character(len=*), intent(in) :: name
            !! material name
        real(wp), intent(in) :: young
            !! Young's modulus [Pa]
        real(wp), intent(in) :: poisson
            !! Poisson's ratio [-]
        real(wp), intent(in) :: density
            !! mass density [kg/m3]

        mat%name = name
        call mat%set_elasticity(young, poisson, density)
    end subroutine new_elastic_material

    !> sigma_{n+1} = sigma_n + (Omega sigma_n - sigma_n Omega) + lambda tr(de) I + 2 G de.
    pure subroutine elastic_update_stress(self, stress, dstrain, omega, dt, state)
        class(elastic_material_type), intent(in) :: self
        real(wp), intent(inout) :: stress(:)
        real(wp), intent(in) :: dstrain(:)
        real(wp), intent(in) :: omega(3)
        real(wp), intent(in) :: dt
        real(wp), intent(inout) :: state(:)

        call add_elastic_trial(self, stress, dstrain, omega)
    end subroutine elastic_update_stress

    !> elastic_update_stress of a block of particles, written out per dimension so that the
    !> loop over the particles vectorises (the stresses of 2D and 3D cases: 4 and 6 rows).
    pure subroutine elastic_update_stress_block(self, n, stress, dstrain, omega, dt, state)
        class(elastic_material_type), intent(in) :: self
        integer, intent(in) :: n
        real(wp), intent(inout) :: stress(:, :)
        real(wp), intent(in) :: dstrain(:, :)
        real(wp), intent(in) :: omega(:, :)
        real(wp), intent(in) :: dt
        real(wp), intent(inout) :: state(:, :)

        integer :: j
        real(wp) :: g2, lame, dvol, s1, s2, s4, w1

        g2 = 2.0_wp*self%shear
        lame = self%lame
        if (size(stress, 1) == 4) then
            do j = 1, n
                ! the Jaumann rotation of mpm_stress (2D), then Hooke
                s1 = stress(1, j)
                s2 = stress(2, j)
                s4 = stress(4, j)
                w1 = omega(1, j)
                dvol = dstrain(1, j) + dstrain(2, j) + dstrain(3, j)
                stress(1, j) = s1 + 2.0_wp*w1*s4 + g2*dstrain(1, j) + lame*dvol
                stress(2, j) = s2 - 2.0_wp*w1*s4 + g2*dstrain(2, j) + lame*dvol
                stress(3, j) = stress(3, j) + g2*dstrain(3, j) + lame*dvol
                stress(4, j) = s4 + w1*(s2 - s1) + g2*dstrain(4, j)
            end do
        else
            do j = 1, n
                call elastic_update_stress(self, stress(:, j), dstrain(:, j), omega(:, j), dt, &
                    state(:, j))
            end do
        end if
    end subroutine elastic_update_stress_block

end module mpm_material_elastic
